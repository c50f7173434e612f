#include "persistence/checkpoint.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <span>
#include <stdexcept>

#include "common/hash.hpp"
#include "persistence/record_codec.hpp"

namespace treedyn::persistence {
namespace fs = std::filesystem;
namespace {

fs::path state_path(const fs::path& dir, const std::string& stem) { return dir / (stem + ".state"); }
fs::path records_path(const fs::path& dir, const std::string& stem) { return dir / (stem + ".records"); }
std::string part_stem(std::uint64_t generation, const std::string& name) {
  return "part-" + std::to_string(generation) + "-" + name;
}
std::string base_stem(std::uint64_t generation) { return "base-" + std::to_string(generation); }

// --- Records files: frames of [bytes u64][hash u64][records] ---------------

// A frame is built in place, so that a checkpoint never copies its records:
// open_frame leaves room for the header, seal_frame fills it in.
constexpr std::size_t kFrameHeader = 2 * sizeof(std::uint64_t);

void open_frame(std::vector<char>& frame) { frame.assign(kFrameHeader, '\0'); }

void seal_frame(std::vector<char>& frame) {
  const std::span<const char> records(frame.data() + kFrameHeader, frame.size() - kFrameHeader);
  const std::uint64_t header[2] = {records.size(), hash64(records)};
  std::memcpy(frame.data(), header, kFrameHeader);
}

// The records in the first `bytes` bytes of a records file (frames spilled
// after the last state are not read).
std::vector<SampleRecord> read_frames(const fs::path& path, std::uint64_t bytes) {
  if (bytes == 0) return {};
  const std::vector<char> all = process::read_file_prefix(path, bytes);
  std::vector<SampleRecord> out;
  try {
    if (all.size() < bytes) throw DecodeError(path.string() + " is damaged (truncated)");
    ByteReader in(std::span<const char>(all.data(), bytes), path.string());
    while (!in.done()) {
      const auto size = in.get<std::uint64_t>();
      const auto sum = in.get<std::uint64_t>();
      const std::span<const char> records = in.get_bytes(size);
      if (hash64(records) != sum) in.fail("a frame's hash does not match");
      for (auto& r : read_records(records, path.string())) out.push_back(std::move(r));
    }
  } catch (const DecodeError& e) {
    refuse_damaged(e);
  }
  return out;
}

// --- State files ----------------------------------------------------------

// A part's (or a base's) state: generation, records bytes and count,
// statistics; in its temporary, to be committed.
std::unique_ptr<StateFileWriter> part_state(const fs::path& path, const RunIdentity& id, std::uint64_t generation,
                                            std::uint64_t records_bytes, std::uint64_t records_count,
                                            const statistics::EnsembleStatistics& stats) {
  auto file = std::make_unique<StateFileWriter>(path, StateKind::part, id);
  file->out().put(generation);
  file->out().put(records_bytes);
  file->out().put(records_count);
  for (std::size_t piece = 0; piece < stats.state_pieces(); ++piece) {
    stats.write_state_piece(piece, file->out());
    file->flush_if_large();
  }
  return file;
}

void write_part_state(const fs::path& path, const RunIdentity& id, std::uint64_t generation,
                      std::uint64_t records_bytes, std::uint64_t records_count,
                      const statistics::EnsembleStatistics& stats, process::AtomicFile::Sync sync) {
  part_state(path, id, generation, records_bytes, records_count, stats)->commit(sync);
}

// Adds a part's statistics into `total`; returns its records.
std::vector<SampleRecord> load_part(const fs::path& dir, const std::string& stem, const RunIdentity& id,
                                    const RecordShape& shape, statistics::EnsembleStatistics& total) {
  const fs::path path = state_path(dir, stem);
  const std::vector<char> bytes = process::read_file(path);
  ByteReader in = open_state_file(bytes, StateKind::part, path, &id);
  statistics::EnsembleStatistics part(total.times(), total.columns(), total.bins(), total.calibration());
  std::uint64_t records_bytes = 0, records_count = 0;
  try {
    in.get<std::uint64_t>();  // generation (also in the name)
    records_bytes = in.get<std::uint64_t>();
    records_count = in.get<std::uint64_t>();
    for (std::size_t piece = 0; piece < part.state_pieces(); ++piece) part.add_state_piece(piece, in);
    if (!in.done()) in.fail("bytes after its statistics");
  } catch (const DecodeError& e) {
    refuse_damaged(e);
  }
  std::vector<SampleRecord> records = read_frames(records_path(dir, stem), records_bytes);
  check_records(records, shape, "checkpoint " + path.string());
  const auto ok = std::count_if(records.begin(), records.end(), [&](const auto& r) {
    return r.status == SampleStatus::ok && r.index < shape.statistics_end;
  });
  if (records.size() != records_count || static_cast<std::uint64_t>(ok) != part.samples())
    throw CheckpointError("checkpoint " + path.string() + " is damaged (its records and statistics do not agree)");
  total.merge(part);
  return records;
}

// Whether a refusal is damage, not a checkpoint of another job or build
// (which the whole directory is, and its message says so).
bool damage(const CheckpointError& e) {
  const std::string what = e.what();
  return what.find(" belongs to another job file") == std::string::npos &&
         what.find(" another build ") == std::string::npos;
}

// A damaged or half-missing part (its state or its records): refused with
// the one thing that works, removing both of its files. Its samples then
// run again; every other part is kept.
std::vector<SampleRecord> load_part_or_advise(const fs::path& dir, const std::string& stem, const RunIdentity& id,
                                              const RecordShape& shape, statistics::EnsembleStatistics& total) {
  const fs::path state = state_path(dir, stem), records = records_path(dir, stem);
  const std::string advice =
      fs::exists(records)
          ? "; remove `" + state.string() + "` and `" + records.string() +
                "` together: the samples they hold run again, the rest of the checkpoint is kept"
          : "; remove `" + state.string() + "`: the samples it counts run again, the rest of the checkpoint is kept";
  try {
    return load_part(dir, stem, id, shape, total);
  } catch (const CheckpointError& e) {
    if (!damage(e)) throw;
    throw CheckpointError(e.what() + advice);
  } catch (const process::FileError& e) {
    throw CheckpointError(std::string(e.what()) + advice);
  }
}

// "part-3-rank7" -> 3; -1 when `stem` is not of that form.
long long generation_of(const std::string& stem, const std::string& prefix) {
  if (stem.rfind(prefix, 0) != 0) return -1;
  const std::string rest = stem.substr(prefix.size());
  const std::string digits = rest.substr(0, rest.find('-'));
  if (digits.empty() || digits.size() > 18 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoll(digits);
}

std::vector<std::string> state_stems(const fs::path& dir) {
  std::vector<std::string> stems;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().extension() == ".state") stems.push_back(entry.path().stem().string());
  std::sort(stems.begin(), stems.end());
  return stems;
}

// The stems of the newest generation: its base (G >= 1) and parts. A part
// of generation G exists only once base-G does, so G is the newest of
// either: a base removed for damage leaves its generation's parts in use.
std::pair<std::uint64_t, std::vector<std::string>> newest_generation(const fs::path& dir) {
  std::uint64_t generation = 0;
  const std::vector<std::string> all = state_stems(dir);
  for (const std::string& stem : all)
    generation = std::max<std::uint64_t>(
        generation,
        static_cast<std::uint64_t>(std::max({0LL, generation_of(stem, "base-"), generation_of(stem, "part-")})));
  if (generation > 0 && !fs::exists(state_path(dir, base_stem(generation)))) {
    std::vector<std::string> stems;
    for (const std::string& stem : all)
      if (generation_of(stem, "part-") == static_cast<long long>(generation)) stems.push_back(stem);
    return {generation, stems};
  }
  std::vector<std::string> stems;
  if (generation > 0) stems.push_back(base_stem(generation));
  for (const std::string& stem : all)
    if (generation_of(stem, "part-") == static_cast<long long>(generation)) stems.push_back(stem);
  return {generation, stems};
}

// Sorts the records and lists the [first, end) intervals they cover.
void index_records(RestoredRun& run, const fs::path& dir) {
  std::sort(run.records.begin(), run.records.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  for (std::size_t k = 0; k < run.records.size(); ++k) {
    const std::uint64_t i = run.records[k].index;
    if (k > 0 && run.records[k - 1].index == i)
      throw CheckpointError("checkpoint " + dir.string() + " is damaged (sample " + std::to_string(i) +
                            " twice); remove the directory `" + dir.string() +
                            "` to start afresh (nothing in it "
                            "says which copy to keep)");
    if (!run.finished.empty() && run.finished.back().second == i)
      ++run.finished.back().second;
    else
      run.finished.emplace_back(i, i + 1);
  }
}

}  // namespace

fs::path checkpoint_directory(const fs::path& output) {
  fs::path dir = output;
  dir += ".checkpoint";
  return dir;
}

void write_checkpoint_common(const fs::path& dir, const RunIdentity& id, const std::vector<double>& nominal,
                             const statistics::Calibration& calibration, const statistics::ToleranceCheck& tolerance) {
  StateFileWriter file(state_path(dir, "common"), StateKind::common, id);
  file.out().put_vector(nominal);
  calibration.write(file.out());
  tolerance.write(file.out());
  file.commit(process::AtomicFile::Sync::yes);
}

RankCheckpoint::RankCheckpoint(fs::path dir, RunIdentity id, std::uint64_t generation, const std::string& name)
    : dir_(std::move(dir)), id_(std::move(id)), generation_(generation), name_(name) {}

void RankCheckpoint::add(const SampleRecord& record) {
  if (pending_records_ == 0) open_frame(pending_);
  const std::size_t before = pending_.size();
  try {
    append_record(record, pending_);
  } catch (...) {
    pending_.resize(before);  // no half record for a later save to seal into the frame
    throw;
  }
  ++pending_records_;
  if (pending_.size() >= kSpillBytes) append_pending();
}

fs::path RankCheckpoint::records_file() const { return records_path(dir_, part_stem(generation_, name_)); }
fs::path RankCheckpoint::state_file() const { return state_path(dir_, part_stem(generation_, name_)); }

void RankCheckpoint::refuse_while_prepared() const {
  if (prepared_) throw std::logic_error("a checkpoint save while a prepared one awaits its commit");
}

void RankCheckpoint::refuse_after_failure() const {
  if (failed_)
    throw process::FileError(records_file().string() + ": an earlier write failed; this rank checkpoints no more");
}

// A failed append may leave part of the frame in the file, past every
// offset a state names: it is cut off again where it can be, and this
// checkpoint refuses any further write (a frame after the torn one would
// sit at an offset the states do not know). The caller turns this rank's
// checkpoints off.
void RankCheckpoint::append_pending() {
  refuse_after_failure();
  seal_frame(pending_);
  try {
    process::append_to_file(records_file(), pending_,
                            process::AtomicFile::Sync::no);  // flushed by the save that names it
  } catch (const process::FileError&) {
    failed_ = true;
    std::error_code ignored;
    if (fs::is_regular_file(records_file(), ignored)) fs::resize_file(records_file(), appended_bytes_, ignored);
    throw;
  }
  appended_bytes_ += pending_.size();
  appended_records_ += pending_records_;
  pending_.clear();
  pending_records_ = 0;
}

// One save, as its two steps at once.
void RankCheckpoint::save(const statistics::EnsembleStatistics& stats, process::AtomicFile::Sync sync) {
  prepare_save(stats);
  commit(sync);
}

void RankCheckpoint::prepare_save(const statistics::EnsembleStatistics& stats) {
  refuse_after_failure();
  refuse_while_prepared();
  if (saved_once_ && !has_unsaved()) return;  // the state on disk is this one: commit() flushes it if asked
  if (pending_records_ > 0) append_pending();
  prepared_ = part_state(state_file(), id_, generation_, appended_bytes_, appended_records_, stats);
  prepared_records_ = appended_records_;
}

void RankCheckpoint::commit_prepared() { commit(process::AtomicFile::Sync::yes); }

// The prepared state renamed into place; with Sync::yes the records it
// names are flushed first, then the state and its name.
void RankCheckpoint::commit(process::AtomicFile::Sync sync) {
  refuse_after_failure();
  const bool flush = sync == process::AtomicFile::Sync::yes;
  if (!prepared_) {
    if (flush && saved_once_ && !saved_flushed_) flush_saved();
    return;
  }
  const std::unique_ptr<StateFileWriter> state = std::move(prepared_);  // a failure removes its temporary
  if (flush && prepared_records_ > flushed_records_)
    process::flush_file(records_file());            // the spills and unflushed saves, before the state names them
  if (flush) flushed_records_ = prepared_records_;  // fsync covers the whole file
  state->commit(sync);
  saved_records_ = prepared_records_;
  saved_once_ = true;
  saved_flushed_ = flush;
}

// The last save, made without a flush (a stop signal's, with SIGKILL to
// come), flushed in place when a flushed save of the same state is asked
// (the run's end): its records, its state and their names.
void RankCheckpoint::flush_saved() {
  if (appended_records_ > flushed_records_) process::flush_file(records_file());
  process::flush_file(state_file());
  process::flush_directory(dir_);
  flushed_records_ = appended_records_;
  saved_flushed_ = true;
}

void check_records(const std::vector<SampleRecord>& records, const RecordShape& shape, const std::string& what) {
  for (const SampleRecord& r : records) {
    const bool ok = r.status == SampleStatus::ok;
    const bool fits =
        r.index >= shape.first && r.index < shape.end && (r.inputs.empty() || r.inputs.size() == shape.inputs) &&
        r.reductions.size() == shape.reductions && r.responses.size() == shape.responses &&
        r.final_state.size() == shape.final_state &&
        (r.trajectory.empty() || (ok && r.index < shape.stored && r.trajectory.size() == shape.trajectory));
    if (!fits)
      throw CheckpointError(what + " is damaged or of another job (sample " + std::to_string(r.index) +
                            " does not fit the job's shape); remove it to start afresh");
  }
}

std::optional<RestoredRun> load_checkpoint(const fs::path& dir, const RunIdentity& id, const StatisticsShape& shape,
                                           const RecordShape& record_shape) {
  if (!checkpoint_exists(dir)) return std::nullopt;
  RestoredRun run;
  const fs::path common = state_path(dir, "common");
  try {
    const std::vector<char> bytes = process::read_file(common);
    ByteReader in = open_state_file(bytes, StateKind::common, common, &id);
    run.nominal = in.get_vector<double>();
    if (run.nominal.size() != shape.times * shape.columns) in.fail("a nominal run of another shape");
    run.calibration = statistics::Calibration::read(in, run.nominal.size());
    run.tolerance = statistics::ToleranceCheck::read(in);
  } catch (const DecodeError& e) {
    throw CheckpointError(std::string(e.what()) + "; remove the directory `" + dir.string() +
                          "` to start afresh (common.state holds the pilot's calibration, which every part needs)");
  } catch (const CheckpointError& e) {
    if (!damage(e)) throw;
    throw CheckpointError(std::string(e.what()) + "; remove the directory `" + dir.string() +
                          "` to start afresh (common.state holds the pilot's calibration, which every part needs)");
  } catch (const process::FileError& e) {
    throw CheckpointError(std::string(e.what()) + "; remove the directory `" + dir.string() + "` to start afresh");
  }
  run.statistics.emplace(shape.times, shape.columns, shape.bins, run.calibration);
  const auto [generation, stems] = newest_generation(dir);
  run.generation = generation;
  for (const std::string& stem : stems)
    for (auto& r : load_part_or_advise(dir, stem, id, record_shape, *run.statistics))
      run.records.push_back(std::move(r));
  index_records(run, dir);
  return run;
}

std::uint64_t consolidate_checkpoint(const fs::path& dir, const RunIdentity& id, const RestoredRun& restored) {
  const std::uint64_t next = restored.generation + 1;
  const std::string stem = base_stem(next);
  std::vector<char> framed;
  open_frame(framed);
  for (const SampleRecord& r : restored.records) append_record(r, framed);
  // Records first, then the state that refers to them; each atomically.
  std::uint64_t bytes = 0;
  if (!restored.records.empty()) {
    seal_frame(framed);
    process::write_file_atomically(records_path(dir, stem), framed);
    bytes = framed.size();
  }
  write_part_state(state_path(dir, stem), id, next, bytes, restored.records.size(), *restored.statistics,
                   process::AtomicFile::Sync::yes);
  // Older generations are now contained in base-(G+1).
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string file = entry.path().filename().string();
    const std::string stem_of = file.substr(0, file.find('.'));
    const long long g = std::max(generation_of(stem_of, "part-"), generation_of(stem_of, "base-"));
    if (g >= 0 && static_cast<std::uint64_t>(g) < next) fs::remove(entry.path(), ec);
  }
  return next;
}

bool checkpoint_exists(const fs::path& dir) {
  std::error_code ec;
  const bool exists = fs::exists(state_path(dir, "common"), ec);
  if (ec) throw process::FileError("cannot look into " + dir.string() + ": " + ec.message());
  return exists;
}

bool checkpoint_holds_samples(const fs::path& dir) {
  return checkpoint_exists(dir) && !newest_generation(dir).second.empty();
}

void create_checkpoint_directory(const fs::path& dir) {
  std::error_code ec;
  if (!fs::create_directory(dir, ec))
    throw process::FileError("cannot create the checkpoint directory " + dir.string() + ": " +
                             (ec ? ec.message() : "it exists already"));
  process::flush_directory(process::directory_of(dir));
}

void remove_checkpoint(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  fs::path doomed = dir;
  doomed += ".removing-" + std::to_string(::getpid());
  fs::rename(dir, doomed, ec);
  fs::remove_all(ec ? dir : doomed, ec);
}

}  // namespace treedyn::persistence
