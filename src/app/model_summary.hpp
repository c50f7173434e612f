// Human-readable reports of a model and of a finished run.
#pragma once

#include <ostream>

#include "integrate/settings.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "model/parameters.hpp"
#include "output/recorder.hpp"

namespace treedyn {

// The tree drawn as text, total mass, and each body's mass and augmented
// inertia K_i (about its inboard joint, body frame).
void print_model_summary(std::ostream& out, const Job& job);

// The named parameters (the perturbation targets) with their nominal values,
// units and where they enter; at most `at_most` of them.
void print_parameters(std::ostream& out, const ParameterTable& table, std::size_t at_most);

// Final state, energy drift and integrator statistics.
void print_run_summary(std::ostream& out, const Job& job, const Recorder& recorder, const IntegrationOutcome& outcome,
                       double wall_seconds);

// A readable account of the ensemble: design, inputs (and how often each
// falls outside its parameter's valid range), statistics settings
// (app/ensemble_summary.cpp).
void print_ensemble_summary(std::ostream& out, const Job& job, const EnsembleSpec& spec);

}  // namespace treedyn
