// What rank 0 pays per record, without MPI: for each shipped example, the
// records of real samples (each its own: repeated records compress far
// better than real ones, and deflate is much of the cost) are encoded as a
// sender encodes them, decoded as rank 0 decodes a message, and written by
// the EnsembleWriter as rank 0 writes them, in batches of 1024. CPU time of
// this process (CLOCK_PROCESS_CPUTIME_ID), median of 3 runs; the file goes
// to DIR (default /tmp).
//
//   record_writing_benchmark [DIR] [JOB [write]]    (JOB: one example only;
//     `write`: its write alone, 20 times, to profile it with perf)
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "hdf5/ensemble_file.hpp"
#include "job/sample_job.hpp"
#include "persistence/record_codec.hpp"
#include "timing.hpp"

namespace {

using namespace treedyn;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

constexpr std::size_t kBatch = 1024;

struct Costs {
  double encode = 0, decode = 0, write = 0;  // s per record
  std::size_t bytes = 0;                     // encoded bytes per record
};

Costs measure(const Job& job, const EnsembleSpec& spec, const std::vector<SampleRecord>& all,
              ensemble::SampleRunner& runner, const std::filesystem::path& file) {
  Costs c;
  const std::size_t kRecords = all.size();
  std::vector<char> message;
  double t = cpu_seconds();
  for (const auto& r : all) persistence::append_record(r, message);
  c.encode = (cpu_seconds() - t) / static_cast<double>(kRecords);
  c.bytes = message.size() / kRecords;
  t = cpu_seconds();
  const std::vector<SampleRecord> decoded = persistence::read_records(message, "benchmark");
  c.decode = (cpu_seconds() - t) / static_cast<double>(kRecords);
  EnsembleSpec sized = spec;
  sized.runs = kRecords;
  {
    h5::EnsembleWriter writer(file, job, sized, runner.layout(), runner.final_state_size());
    t = cpu_seconds();
    for (std::size_t first = 0; first < kRecords; first += kBatch)
      writer.write_records(std::vector<SampleRecord>(decoded.begin() + static_cast<std::ptrdiff_t>(first),
                                                     decoded.begin() + static_cast<std::ptrdiff_t>(first + kBatch)));
    c.write = (cpu_seconds() - t) / static_cast<double>(kRecords);
  }  // the temporary file goes with the writer
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path dir = argc > 1 ? argv[1] : std::filesystem::temp_directory_path();
  std::printf(
      "| job | record (bytes, encoded) | encode (us) | decode (us) | write (us) | rank 0 per received record (us) |\n"
      "|---|---:|---:|---:|---:|---:|\n");
  for (const char* name : {"spherical_pendulum", "double_pendulum", "chain10", "y_tree", "crane_payload", "kapitza"}) {
    if (argc > 2 && std::string(argv[2]) != name) continue;
    auto [job, spec] = read_ensemble_job(JobDocument::read(std::string(TREEDYN_JOBS_DIR) + "/" + name + ".toml"));
    spec.runs = 16 * kBatch;  // sample indices for every record below
    ensemble::SampleRunner runner(job, spec);
    std::vector<double> trajectory;
    // About 10 s of samples, in whole batches.
    const auto start = bench::Clock::now();
    std::vector<SampleRecord> real;
    while (real.size() < kBatch || (real.size() % kBatch != 0) ||
           (bench::seconds_since(start) < 10.0 && real.size() < 16 * kBatch)) {
      real.push_back(runner.run(real.size(), false, trajectory));
      real.back().trajectory.clear();  // stored trajectories are a few samples' only
    }
    std::vector<Costs> runs;
    if (argc > 3) {  // the write alone, for a profile
      for (int repeat = 0; repeat < 20; ++repeat) runs.push_back(measure(job, spec, real, runner, dir / "profile.h5"));
      std::printf("write %.2f us per record\n", runs.back().write * 1e6);
      continue;
    }
    for (int repeat = 0; repeat < 3; ++repeat)
      runs.push_back(measure(job, spec, real, runner, dir / (std::string(name) + "_records.h5")));
    auto middle = [&](double Costs::*field) {
      std::vector<double> v;
      for (const Costs& c : runs) v.push_back(c.*field);
      return bench::median(v) * 1e6;
    };
    std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f |\n", name, runs[0].bytes, middle(&Costs::encode),
                middle(&Costs::decode), middle(&Costs::write), middle(&Costs::decode) + middle(&Costs::write));
  }
  return 0;
}
