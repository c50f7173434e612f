#include "ensemble/checkpoint.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "ensemble/record_codec.hpp"

namespace treedyn::ensemble {
namespace fs = std::filesystem;
namespace {

constexpr char kMagic[8] = {'T', 'D', 'C', 'K', 'P', 'T', '0', '1'};
enum class Kind : std::uint32_t { common = 1, part = 2, part_file = 3 };

std::uint64_t fnv1a(const char* data, std::size_t size, std::uint64_t h = 14695981039346656037ull) {
  for (std::size_t k = 0; k < size; ++k) {
    h ^= static_cast<unsigned char>(data[k]);
    h *= 1099511628211ull;
  }
  return h;
}

std::string hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

// --- Bytes out and in -------------------------------------------------------

class Out {
 public:
  template <class T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    b_.insert(b_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    const auto* p = reinterpret_cast<const char*>(v.data());
    b_.insert(b_.end(), p, p + v.size() * sizeof(T));
  }
  void put_text(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    b_.insert(b_.end(), s.begin(), s.end());
  }
  std::vector<char>& bytes() { return b_; }

 private:
  std::vector<char> b_;
};

class In {
 public:
  In(const char* data, std::size_t size, std::string what) : d_(data), n_(size), what_(std::move(what)) {}
  template <class T>
  T get() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, d_ + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto count = get<std::uint64_t>();
    if (count > (n_ - at_) / sizeof(T)) fail("truncated");
    std::vector<T> v(count);
    if (count > 0) std::memcpy(v.data(), d_ + at_, count * sizeof(T));
    at_ += count * sizeof(T);
    return v;
  }
  std::string get_text() {
    const auto count = get<std::uint64_t>();
    need(count);
    std::string s(d_ + at_, count);
    at_ += count;
    return s;
  }
  std::size_t at() const { return at_; }
  [[noreturn]] void fail(const std::string& why) const {
    throw CheckpointError("checkpoint " + what_ + " is damaged (" + why + "); remove it to start afresh");
  }

 private:
  void need(std::size_t count) const {
    if (count > n_ - at_) fail("truncated");
  }
  const char* d_;
  std::size_t n_;
  std::size_t at_ = 0;
  std::string what_;
};

// --- Files ------------------------------------------------------------------

std::vector<char> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError("cannot read checkpoint file " + path.string());
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytes;
}

void write_all(int fd, const char* data, std::size_t size, const fs::path& path) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw CheckpointError("writing checkpoint file " + path.string() + ": " + std::strerror(errno));
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

// Written to PATH.tmp-PID, flushed to the disk, renamed over PATH.
void write_atomically(const fs::path& path, const std::vector<char>& bytes) {
  fs::path temporary = path;
  temporary += ".tmp-" + std::to_string(getpid());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw CheckpointError("creating checkpoint file " + temporary.string() + ": " + std::strerror(errno));
  try {
    write_all(fd, bytes.data(), bytes.size(), temporary);
    if (::fsync(fd) != 0) throw CheckpointError("flushing " + temporary.string() + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  if (::close(fd) != 0 || std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(temporary.c_str());
    throw CheckpointError("writing checkpoint file " + path.string() + ": " + why);
  }
}

// A state file: magic, kind, identity, payload, checksum of all before it.
std::vector<char> state_bytes(Kind kind, const CheckpointIdentity& id, Out& payload) {
  Out out;
  for (char c : kMagic) out.put(c);
  out.put(static_cast<std::uint32_t>(kind));
  out.put_text(id.job_hash);
  out.put_text(id.build);
  auto& b = out.bytes();
  b.insert(b.end(), payload.bytes().begin(), payload.bytes().end());
  out.put(fnv1a(b.data(), b.size()));
  return b;
}

// Checks magic, checksum and identity (when `id` is given; else stores what
// the file says in `found`); returns the payload reader position.
In open_state(const std::vector<char>& bytes, Kind kind, const CheckpointIdentity* id, const fs::path& path,
              CheckpointIdentity* found = nullptr) {
  const std::string what = path.string();
  if (bytes.size() < sizeof kMagic + 12 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw CheckpointError("checkpoint " + what + " is not a treedyn checkpoint (or from another layout)");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  In in(bytes.data(), bytes.size() - 8, what);
  if (fnv1a(bytes.data(), bytes.size() - 8) != stored) in.fail("checksum mismatch");
  for (std::size_t k = 0; k < sizeof kMagic; ++k) in.get<char>();
  if (in.get<std::uint32_t>() != static_cast<std::uint32_t>(kind)) in.fail("unexpected kind");
  const std::string job_hash = in.get_text();
  const std::string build = in.get_text();
  if (found) *found = {job_hash, build};
  if (!id) return in;
  if (job_hash != id->job_hash)
    throw CheckpointError("checkpoint " + what + " belongs to another job file (job text hash " + job_hash +
                          ", this job's is " + id->job_hash +
                          "): resume with the job file it was started with, or remove the checkpoint");
  if (build != id->build)
    throw CheckpointError("checkpoint " + what + " was written by another build (" + build + "; this is " +
                          id->build + "): resume with that build, or remove the checkpoint");
  return in;
}

void put_statistics(Out& out, EnsembleStatistics& s) {
  out.put(s.sample_count());
  out.put_vector(s.sums());
  out.put_vector(s.square_sums());
  out.put_vector(s.minima());
  out.put_vector(s.maxima());
  out.put_vector(s.counts());
  out.put_vector(s.out_of_range_counts());
}

// The raw statistics of a payload, checked against the job's shape, as bytes.
std::vector<char> take_statistics(In& in, std::size_t entries, int bins) {
  Out out;
  out.put(in.get<std::uint64_t>());
  auto sums = in.get_vector<wide>();
  auto squares = in.get_vector<wide>();
  auto minima = in.get_vector<double>();
  auto maxima = in.get_vector<double>();
  auto counts = in.get_vector<std::uint32_t>();
  auto out_of_range = in.get_vector<std::uint64_t>();
  const std::size_t bin_entries = entries * static_cast<std::size_t>(bins + 2);
  if (sums.size() != entries || squares.size() != entries || minima.size() != entries ||
      maxima.size() != entries || counts.size() != bin_entries || out_of_range.size() != entries)
    in.fail("statistics of another shape");
  out.put_vector(sums);
  out.put_vector(squares);
  out.put_vector(minima);
  out.put_vector(maxima);
  out.put_vector(counts);
  out.put_vector(out_of_range);
  return std::move(out.bytes());
}

// Element-wise sum of two raw statistics (exact: integers, min, max).
void add_statistics(std::vector<char>& total, const std::vector<char>& part) {
  if (total.empty()) {
    total = part;
    return;
  }
  In a(total.data(), total.size(), "(sum)"), b(part.data(), part.size(), "(part)");
  Out out;
  out.put(a.get<std::uint64_t>() + b.get<std::uint64_t>());
  auto sum = [&](auto x, auto y) {
    for (std::size_t k = 0; k < x.size(); ++k) x[k] += y[k];
    out.put_vector(x);
  };
  sum(a.get_vector<wide>(), b.get_vector<wide>());
  sum(a.get_vector<wide>(), b.get_vector<wide>());
  auto lo = a.get_vector<double>(), lo_b = b.get_vector<double>();
  for (std::size_t k = 0; k < lo.size(); ++k) lo[k] = std::min(lo[k], lo_b[k]);
  out.put_vector(lo);
  auto hi = a.get_vector<double>(), hi_b = b.get_vector<double>();
  for (std::size_t k = 0; k < hi.size(); ++k) hi[k] = std::max(hi[k], hi_b[k]);
  out.put_vector(hi);
  sum(a.get_vector<std::uint32_t>(), b.get_vector<std::uint32_t>());
  sum(a.get_vector<std::uint64_t>(), b.get_vector<std::uint64_t>());
  total = std::move(out.bytes());
}

// Records files: frames of [bytes u64][checksum u64][append_record bytes].
void append_frame(const fs::path& path, const std::vector<char>& records) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError("opening checkpoint file " + path.string() + ": " + std::strerror(errno));
  try {
    const std::uint64_t header[2] = {records.size(), fnv1a(records.data(), records.size())};
    write_all(fd, reinterpret_cast<const char*>(header), sizeof header, path);
    write_all(fd, records.data(), records.size(), path);
    if (::fsync(fd) != 0) throw CheckpointError("flushing " + path.string() + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw CheckpointError("closing " + path.string() + ": " + std::strerror(errno));
}

// The first `bytes` bytes of a records file, decoded.
std::vector<SampleRecord> read_frames(const fs::path& path, std::uint64_t bytes) {
  if (bytes == 0) return {};
  const std::vector<char> all = read_file(path);
  if (all.size() < bytes) throw CheckpointError("checkpoint " + path.string() + " is damaged (truncated)");
  std::vector<SampleRecord> out;
  std::size_t at = 0;
  while (at < bytes) {
    In in(all.data() + at, bytes - at, path.string());
    const auto size = in.get<std::uint64_t>();
    const auto sum = in.get<std::uint64_t>();
    if (size > bytes - at - 16) in.fail("frame beyond the saved length");
    const char* data = all.data() + at + 16;
    if (fnv1a(data, size) != sum) in.fail("frame checksum mismatch");
    std::vector<SampleRecord> records;
    try {
      records = read_records(std::vector<char>(data, data + size));
    } catch (const std::exception& e) {
      in.fail(e.what());
    }
    for (auto& r : records) out.push_back(std::move(r));
    at += 16 + size;
  }
  return out;
}

fs::path state_path(const fs::path& dir, const std::string& stem) { return dir / (stem + ".state"); }
fs::path records_path(const fs::path& dir, const std::string& stem) { return dir / (stem + ".records"); }
std::string part_stem(std::uint64_t generation, const std::string& name) {
  return "part-" + std::to_string(generation) + "-" + name;
}
std::string base_stem(std::uint64_t generation) { return "base-" + std::to_string(generation); }

// A part's or a base's state: generation, records bytes and count, statistics.
struct PartState {
  std::uint64_t records_bytes = 0, records_count = 0;
  std::vector<char> statistics;
};

PartState read_part(const fs::path& path, const CheckpointIdentity& id, std::size_t entries, int bins) {
  const std::vector<char> bytes = read_file(path);
  In in = open_state(bytes, Kind::part, &id, path);
  PartState p;
  in.get<std::uint64_t>();  // generation (also in the name)
  p.records_bytes = in.get<std::uint64_t>();
  p.records_count = in.get<std::uint64_t>();
  p.statistics = take_statistics(in, entries, bins);
  return p;
}

std::vector<char> part_state_bytes(const CheckpointIdentity& id, std::uint64_t generation,
                                   std::uint64_t records_bytes, std::uint64_t records_count,
                                   const std::vector<char>& raw_statistics) {
  Out payload;
  payload.put(generation);
  payload.put(records_bytes);
  payload.put(records_count);
  auto& b = payload.bytes();
  b.insert(b.end(), raw_statistics.begin(), raw_statistics.end());
  return state_bytes(Kind::part, id, payload);
}

// "part-3-rank7" -> 3; -1 when `stem` is not of that form.
long long generation_of(const std::string& stem, const std::string& prefix) {
  if (stem.rfind(prefix, 0) != 0) return -1;
  const std::string rest = stem.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  const std::string digits = dash == std::string::npos ? rest : rest.substr(0, dash);
  if (digits.empty() || digits.size() > 18 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoll(digits);
}

std::vector<std::string> stems_with_suffix(const fs::path& dir, const std::string& suffix) {
  std::vector<std::string> stems;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.size() > suffix.size() && file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0)
      stems.push_back(file.substr(0, file.size() - suffix.size()));
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

}  // namespace

CheckpointIdentity checkpoint_identity(const std::string& job_text, const std::string& build) {
  return {hex(fnv1a(job_text.data(), job_text.size())), build};
}

fs::path checkpoint_directory(const fs::path& output) {
  fs::path dir = output;
  dir += ".checkpoint";
  return dir;
}

void write_checkpoint_common(const fs::path& dir, const CheckpointIdentity& id, const std::vector<double>& nominal,
                             const Calibration& calibration) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CheckpointError("creating checkpoint directory " + dir.string() + ": " + ec.message());
  Out payload;
  payload.put_vector(nominal);
  payload.put_vector(calibration.center);
  payload.put_vector(calibration.scale);
  payload.put_vector(calibration.low);
  payload.put_vector(calibration.width);
  write_atomically(state_path(dir, "common"), state_bytes(Kind::common, id, payload));
}

RankCheckpoint::RankCheckpoint(fs::path dir, CheckpointIdentity id, std::uint64_t generation, const std::string& name)
    : dir_(std::move(dir)), id_(std::move(id)), generation_(generation), name_(name) {}

void RankCheckpoint::add(const SampleRecord& record) {
  append_record(record, pending_);
  ++pending_records_;
}

void RankCheckpoint::save(EnsembleStatistics& stats) {
  const std::string stem = part_stem(generation_, name_);
  if (!pending_.empty()) {
    append_frame(records_path(dir_, stem), pending_);
    saved_bytes_ += 16 + pending_.size();
    saved_records_ += pending_records_;
    pending_.clear();
    pending_records_ = 0;
  }
  Out raw;
  put_statistics(raw, stats);
  write_atomically(state_path(dir_, stem), part_state_bytes(id_, generation_, saved_bytes_, saved_records_, raw.bytes()));
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

void check_calibration(const Calibration& c, std::size_t entries, const std::string& what) {
  bool fine = c.center.size() == entries && c.scale.size() == entries && c.low.size() == entries &&
              c.width.size() == entries;
  for (std::size_t e = 0; fine && e < entries; ++e)
    fine = std::isfinite(c.center[e]) && std::isfinite(c.low[e]) && c.scale[e] > 0.0 && std::isfinite(c.scale[e]) &&
           c.width[e] > 0.0 && std::isfinite(c.width[e]);
  if (!fine) throw CheckpointError(what + " is damaged (its calibration is not usable); remove it to start afresh");
}

std::optional<RestoredRun> load_checkpoint(const fs::path& dir, const CheckpointIdentity& id, std::size_t entries,
                                           int bins, const RecordShape& shape) {
  std::error_code ec;
  const bool exists = fs::exists(state_path(dir, "common"), ec);
  if (ec) throw CheckpointError("cannot look into " + dir.string() + ": " + ec.message());
  if (!exists) return std::nullopt;
  RestoredRun run;
  {
    const fs::path path = state_path(dir, "common");
    const std::vector<char> bytes = read_file(path);
    In in = open_state(bytes, Kind::common, &id, path);
    run.nominal = in.get_vector<double>();
    run.calibration.center = in.get_vector<double>();
    run.calibration.scale = in.get_vector<double>();
    run.calibration.low = in.get_vector<double>();
    run.calibration.width = in.get_vector<double>();
    if (run.nominal.size() != entries) in.fail("nominal run of another shape");
    check_calibration(run.calibration, entries, "checkpoint " + path.string());
  }
  // The newest complete generation: 0, or one with its base.
  std::uint64_t generation = 0;
  for (const std::string& stem : stems_with_suffix(dir, ".state"))
    if (const long long g = generation_of(stem, "base-"); g > static_cast<long long>(generation)) generation = g;
  run.generation = generation;
  std::vector<std::string> stems;
  if (generation > 0) stems.push_back(base_stem(generation));
  for (const std::string& stem : stems_with_suffix(dir, ".state"))
    if (generation_of(stem, "part-") == static_cast<long long>(generation)) stems.push_back(stem);
  for (const std::string& stem : stems) {
    const PartState part = read_part(state_path(dir, stem), id, entries, bins);
    std::vector<SampleRecord> records = read_frames(records_path(dir, stem), part.records_bytes);
    check_records(records, shape, "checkpoint " + state_path(dir, stem).string());
    if (records.size() != part.records_count)
      throw CheckpointError("checkpoint " + state_path(dir, stem).string() +
                            " is damaged (record count mismatch); remove it to start afresh");
    add_statistics(run.statistics, part.statistics);
    for (auto& r : records) run.records.push_back(std::move(r));
  }
  std::sort(run.records.begin(), run.records.end(),
            [](const SampleRecord& a, const SampleRecord& b) { return a.index < b.index; });
  for (std::size_t k = 0; k < run.records.size(); ++k) {
    const std::uint64_t i = run.records[k].index;
    if (k > 0 && run.records[k - 1].index == i)
      throw CheckpointError("checkpoint " + dir.string() + " is damaged (sample " + std::to_string(i) +
                            " twice); remove it to start afresh");
    if (run.records[k].status == SampleStatus::ok) ++run.ok_samples;
    if (!run.finished.empty() && run.finished.back().second == i)
      ++run.finished.back().second;
    else
      run.finished.emplace_back(i, i + 1);
  }
  if (!run.statistics.empty()) {
    std::uint64_t counted = 0;
    std::memcpy(&counted, run.statistics.data(), sizeof counted);
    if (counted != run.ok_samples)
      throw CheckpointError("checkpoint " + dir.string() + " is damaged (statistics count " +
                            std::to_string(counted) + " samples, the records " + std::to_string(run.ok_samples) +
                            "); remove it to start afresh");
  }
  return run;
}

void restore_statistics(const std::vector<char>& raw, EnsembleStatistics& stats) {
  if (raw.empty()) return;
  Out mine;
  put_statistics(mine, stats);
  std::vector<char> total = mine.bytes();
  add_statistics(total, raw);
  In in(total.data(), total.size(), "(restored statistics)");
  stats.sample_count() = in.get<std::uint64_t>();
  stats.sums() = in.get_vector<wide>();
  stats.square_sums() = in.get_vector<wide>();
  stats.minima() = in.get_vector<double>();
  stats.maxima() = in.get_vector<double>();
  stats.counts() = in.get_vector<std::uint32_t>();
  stats.out_of_range_counts() = in.get_vector<std::uint64_t>();
}

std::uint64_t consolidate_checkpoint(const fs::path& dir, const CheckpointIdentity& id, const RestoredRun& restored,
                                     EnsembleStatistics& restored_stats) {
  const std::uint64_t next = restored.generation + 1;
  const std::string stem = base_stem(next);
  std::vector<char> records;
  for (const SampleRecord& r : restored.records) append_record(r, records);
  // Records first, then the state that refers to them; each atomically.
  std::uint64_t bytes = 0;
  {
    Out frame;
    const std::uint64_t header[2] = {records.size(), fnv1a(records.data(), records.size())};
    frame.put(header[0]);
    frame.put(header[1]);
    auto& b = frame.bytes();
    b.insert(b.end(), records.begin(), records.end());
    if (!records.empty()) {
      write_atomically(records_path(dir, stem), b);
      bytes = b.size();
    }
  }
  Out statistics;
  put_statistics(statistics, restored_stats);
  write_atomically(state_path(dir, stem), part_state_bytes(id, next, bytes, restored.records.size(), statistics.bytes()));
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

void remove_checkpoint(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  fs::path doomed = dir;
  doomed += ".removing-" + std::to_string(getpid());
  fs::rename(dir, doomed, ec);
  fs::remove_all(ec ? dir : doomed, ec);
}

std::vector<std::string> remove_stale_temporaries(const fs::path& dir, const std::string& name) {
  std::vector<std::string> removed;
  const std::string marker = name + ".tmp-";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec)) {
    const std::string file = entry.path().filename().string();
    const std::size_t at = file.find(".tmp-");
    if (at == std::string::npos || (!name.empty() && file.rfind(marker, 0) != 0)) continue;
    const std::string digits = file.substr(at + 5);
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    if (pid == getpid()) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to tell)
    std::error_code remove_error;
    if (fs::remove(entry.path(), remove_error)) removed.push_back(entry.path().string());
  }
  return removed;
}

void write_part_file(const fs::path& path, const PartFile& part, EnsembleStatistics& stats) {
  Out payload;
  payload.put_text(part.job_text);
  payload.put_text(part.job_path);
  payload.put(part.first);
  payload.put(part.end);
  payload.put_vector(part.nominal);
  payload.put_vector(part.calibration.center);
  payload.put_vector(part.calibration.scale);
  payload.put_vector(part.calibration.low);
  payload.put_vector(part.calibration.width);
  put_statistics(payload, stats);
  std::vector<char> records;
  for (const SampleRecord& r : part.records) append_record(r, records);
  payload.put_vector(records);
  write_atomically(path, state_bytes(Kind::part_file, part.id, payload));
}

PartFile read_part_file(const fs::path& path) {
  const std::vector<char> bytes = read_file(path);
  PartFile part;
  In in = open_state(bytes, Kind::part_file, nullptr, path, &part.id);
  part.job_text = in.get_text();
  part.job_path = in.get_text();
  part.first = in.get<std::uint64_t>();
  part.end = in.get<std::uint64_t>();
  part.nominal = in.get_vector<double>();
  part.calibration.center = in.get_vector<double>();
  part.calibration.scale = in.get_vector<double>();
  part.calibration.low = in.get_vector<double>();
  part.calibration.width = in.get_vector<double>();
  const std::size_t entries = part.nominal.size();
  for (const auto* v : {&part.calibration.center, &part.calibration.scale, &part.calibration.low,
                        &part.calibration.width})
    if (v->size() != entries) in.fail("calibration of another shape than the nominal run");
  // Bins from the counts' length: entries x (bins + 2).
  In peek = in;
  peek.get<std::uint64_t>();
  for (int k = 0; k < 2; ++k) peek.get_vector<wide>();
  for (int k = 0; k < 2; ++k) peek.get_vector<double>();
  const auto counts = peek.get_vector<std::uint32_t>();
  if (entries == 0 || counts.size() % entries != 0 || counts.size() / entries < 3) in.fail("histogram of another shape");
  part.bins = static_cast<int>(counts.size() / entries) - 2;
  part.statistics = take_statistics(in, entries, part.bins);
  const std::vector<char> records = in.get_vector<char>();
  try {
    part.records = read_records(records);
  } catch (const std::exception& e) {
    in.fail(e.what());
  }
  if (part.first > part.end) in.fail("sample range reversed");
  check_calibration(part.calibration, entries, "part file " + path.string());
  // Exactly the samples of its range, once each, and statistics of its ok ones.
  std::uint64_t ok = 0;
  for (std::size_t k = 0; k < part.records.size(); ++k) {
    if (part.records[k].index != part.first + k) in.fail("the samples of its range are not all there, once each");
    if (part.records[k].status == SampleStatus::ok) ++ok;
  }
  if (part.records.size() != part.end - part.first) in.fail("the samples of its range are not all there");
  std::uint64_t counted = 0;
  std::memcpy(&counted, part.statistics.data(), sizeof counted);
  if (counted != ok) in.fail("its statistics do not count its successful samples");
  return part;
}

}  // namespace treedyn::ensemble
