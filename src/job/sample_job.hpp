// One ensemble sample as a job of its own. `treedyn-ensemble --write-job K`
// writes the job's text without [ensemble], plus a [sample] section that
// lists sample K's inputs (SI, printed so they read back to the same
// doubles) with their targets and modes. Reading such a job applies them to
// the nominal parameter vector and initial state by the same code, in the
// same order, as the ensemble did, so `treedyn run` of it reproduces the
// sample bitwise.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "job/ensemble_spec.hpp"
#include "job/job.hpp"

namespace treedyn {

// Applies the job's [sample] section, if it has one: the sample's parameter
// vector and initial state become the job's nominal ones (job.model is
// derived again). Throws JobError naming the field.
void apply_sample_section(Job& job);

// read_job(), then apply_sample_section(): what every command reads.
Job read_sample_job(const JobDocument& document);
Job load_job(const std::filesystem::path& path);

// The job and its [ensemble], from one parse of the text.
struct EnsembleJob {
  Job job;
  EnsembleSpec spec;
};
EnsembleJob read_ensemble_job(const JobDocument& document);

// Throws JobError when the job has a [sample] section (sample jobs are
// written from the original ensemble job only).
void require_not_a_sample_job(const Job& job);

// The text of the standalone job of sample k (inputs: its sampled values,
// SI). Throws JobError when the job already is a sample job.
std::string sample_job_text(const Job& job, const EnsembleSpec& spec, std::uint64_t k, std::span<const double> inputs);

}  // namespace treedyn
