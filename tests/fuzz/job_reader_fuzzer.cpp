// Fuzz target for the job reader: arbitrary bytes as a job file, through
// everything `treedyn-ensemble --check` reads (TOML, the model and its
// physical checks, the initial state, the output, a [sample] section, the
// [ensemble] with its targets and designs). A refusal (JobError) is the
// expected answer to bad input; anything else (another exception, a crash,
// a sanitizer report) is a bug.
//
// Built two ways (tests/CMakeLists.txt): with clang, a libFuzzer binary
// (job_reader_fuzzer CORPUS_DIR ...); always, a replay of every file of
// tests/fuzz/corpus, registered with CTest, so that the seeds and every crash
// found so far are run by the normal test suite.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "job/job_error.hpp"
#include "job/sample_job.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    treedyn::Job job = treedyn::parse_job(text, "fuzz.toml");
    treedyn::apply_sample_section(job);
    if (job.text.find("[ensemble") != std::string::npos) (void)treedyn::read_ensemble(job);
  } catch (const treedyn::JobError&) {
    // A refusal with its location: the reader's answer to bad input.
  }
  return 0;
}
