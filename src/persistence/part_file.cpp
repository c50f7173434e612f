#include "persistence/part_file.hpp"

#include "persistence/record_codec.hpp"

namespace treedyn::persistence {
namespace {

// Exactly the samples of its range, once each, in order.
void check_range(const PartFile& part, ByteReader& in) {
  if (part.first > part.end) in.fail("its sample range is reversed");
  if (part.records.size() != part.end - part.first) in.fail("the samples of its range are not all there");
  for (std::size_t k = 0; k < part.records.size(); ++k)
    if (part.records[k].index != part.first + k) in.fail("the samples of its range are not all there, once each");
}

}  // namespace

void write_part_file(const std::filesystem::path& path, const PartFile& part,
                     const statistics::EnsembleStatistics& stats) {
  StateFileWriter file(path, StateKind::part_file, part.id);
  ByteWriter& out = file.out();
  out.put_text(part.job_text);
  out.put_text(part.job_path);
  out.put(part.first);
  out.put(part.end);
  out.put_vector(part.nominal);
  part.calibration.write(out);
  part.tolerance.write(out);
  file.put_large(stats.state());
  out.put(static_cast<std::uint64_t>(part.records.size()));
  for (const SampleRecord& r : part.records) {
    write_record(r, out);
    file.flush_if_large();
  }
  file.commit(process::AtomicFile::Sync::yes);
}

PartFile read_part_file(const std::filesystem::path& path) {
  const std::vector<char> bytes = process::read_file(path);
  PartFile part;
  ByteReader in = open_state_file(bytes, StateKind::part_file, path, nullptr, &part.id);
  try {
    part.job_text = in.get_text();
    part.job_path = in.get_text();
    part.first = in.get<std::uint64_t>();
    part.end = in.get<std::uint64_t>();
    part.nominal = in.get_vector<double>();
    part.calibration = statistics::Calibration::read(in, part.nominal.size());
    part.tolerance = statistics::ToleranceCheck::read(in);
    part.statistics = in.get_vector<char>();
    const auto count = in.get<std::uint64_t>();
    if (count > in.left()) in.fail("more records than bytes");
    for (std::uint64_t k = 0; k < count; ++k) part.records.push_back(read_record(in));
    if (!in.done()) in.fail("bytes after its records");
    check_range(part, in);
  } catch (const DecodeError& e) {
    throw CheckpointError("part file " + std::string(e.what()));
  }
  return part;
}

}  // namespace treedyn::persistence
