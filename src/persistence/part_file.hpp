// A part of a split ensemble (--samples FIRST:END): everything the merge
// needs, in one enveloped file (persistence/state_file.hpp) written
// atomically, with the identity of the job and build and the job text
// itself, so that the merge needs no job file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "output/sample_record.hpp"
#include "persistence/state_file.hpp"
#include "statistics/ensemble_statistics.hpp"
#include "statistics/tolerance_check.hpp"

namespace treedyn::persistence {

struct PartFile {
  RunIdentity id;
  std::string job_text, job_path;
  std::uint64_t first = 0, end = 0;  // the sample indices it covers, [first, end)
  std::vector<double> nominal;
  statistics::Calibration calibration;
  statistics::ToleranceCheck tolerance;  // the pilot's, the same in every part
  std::vector<char> statistics;          // its statistics' state (EnsembleStatistics::add_state)
  std::vector<SampleRecord> records;     // every sample of the range, by index
};

// Writes `part` with the statistics of `stats` (part.statistics is not
// used). Throws process::FileError.
void write_part_file(const std::filesystem::path& path, const PartFile& part,
                     const statistics::EnsembleStatistics& stats);
// Throws CheckpointError for a file that is not a part or is damaged (its
// records must be exactly those of its range), process::FileError when it
// cannot be read.
PartFile read_part_file(const std::filesystem::path& path);

}  // namespace treedyn::persistence
