// The parsed table of a JobDocument, for the readers in src/job (the only
// files that see toml++).
#pragma once

#include <toml++/toml.h>

#include "job/job_document.hpp"

namespace treedyn {

struct JobDocument::Parsed {
  std::string text, file;
  toml::table root;
};

inline const toml::table& root_table(const JobDocument& document) { return document.parsed().root; }

}  // namespace treedyn
