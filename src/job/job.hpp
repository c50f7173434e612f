// A job: everything one run needs, read from a TOML job file.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "integrate/simulate.hpp"
#include "model/model.hpp"

namespace treedyn {

// A point fixed in a body whose position is recorded (quantity "point_position").
struct OutputPoint {
  std::string name;
  std::string body;
  Vec3 point = Vec3::Zero();  // from the body's CoM, body frame, m
  int body_index = -1;        // index in ModelSpec::bodies, set by the reader
};

struct OutputSpec {
  std::vector<std::string> quantities;  // names from quantity_catalogue()
  std::vector<OutputPoint> points;
};

struct Job {
  std::string file;      // as given by the user
  std::string text;      // the job file's text, stored with the results
  std::string title;
  Model model;           // validated
  SimulationRequest request;
  OutputSpec output;
  // Per body (user order): the initial angular velocity's body-frame
  // components when the job gave them so (it then turns with the body if a
  // perturbation changes the body's orientation).
  std::vector<std::optional<Vec3>> spin_in_body_frame;
};

// Reads and validates a job file. Throws JobError (file, line, column, field,
// what was wrong and what is allowed) for anything it refuses.
Job read_job(const std::filesystem::path& path);
// Same, from text; `file` names it in messages.
Job parse_job(std::string_view text, const std::string& file);

}  // namespace treedyn
