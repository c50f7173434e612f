// A job: everything one run needs, read from a TOML job file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "integrate/simulate.hpp"
#include "job/job_document.hpp"
#include "model/definition.hpp"
#include "model/initial_state.hpp"
#include "model/model.hpp"
#include "output/output_spec.hpp"

namespace treedyn {

struct Job {
  std::string file;      // as given by the user
  std::string text;      // the job file's text, stored with the results
  JobDocument document;  // the text, parsed once: [ensemble] and [sample] read it too
  std::string title;
  ModelDefinition definition;  // the tree, the named parameters (nominal values), fixed inputs
  Model model;                 // the nominal model, derived from definition.parameters.nominal()
  InitialState initial;        // the nominal initial state
  SimulationRequest request;   // output times, parameterisation, integrator settings
  OutputSpec output;
};

// Reads and validates a job: everything but [ensemble] and [sample] (see
// job/sample_job.hpp and job/ensemble_spec.hpp). Throws JobError (file,
// line, column, field, what was wrong and what is allowed) for anything it
// refuses.
Job read_job(const JobDocument& document);
// The same from a file, or from text (`file` names it in messages).
Job read_job(const std::filesystem::path& path);
Job parse_job(std::string_view text, const std::string& file);

}  // namespace treedyn
