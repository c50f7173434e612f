// A job: everything one run needs, read from a TOML job file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "integrate/simulate.hpp"
#include "model/definition.hpp"
#include "model/initial_state.hpp"
#include "model/model.hpp"
#include "output/output_spec.hpp"

namespace treedyn {

struct Job {
  std::string file;      // as given by the user
  std::string text;      // the job file's text, stored with the results
  std::string title;
  ModelDefinition definition;  // the tree, the named parameters (nominal values), fixed inputs
  Model model;                 // the nominal model, derived from definition.parameters.nominal()
  InitialState initial;        // the nominal initial state
  SimulationRequest request;   // output times, parameterisation, integrator settings
  OutputSpec output;
};

// Reads and validates a job file. Throws JobError (file, line, column, field,
// what was wrong and what is allowed) for anything it refuses.
Job read_job(const std::filesystem::path& path);
// Same, from text; `file` names it in messages.
Job parse_job(std::string_view text, const std::string& file);

}  // namespace treedyn
