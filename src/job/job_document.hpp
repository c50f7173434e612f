// A job file's text, parsed once. Every reader of the job (the model and its
// initial state, [integrator], [output], [ensemble], [sample], and
// --write-job) reads this one parsed table; copies share it.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

namespace treedyn {

class JobDocument {
 public:
  JobDocument() = default;
  // Checks the text (toml_guard.hpp) and parses it. Throws JobError
  // (FILE:LINE:COLUMN) for text that is not valid TOML.
  static JobDocument parse(std::string text, std::string file);
  // Reads the file first. Throws JobError when it cannot be read.
  static JobDocument read(const std::filesystem::path& path);

  const std::string& text() const;
  const std::string& file() const;
  bool has(const std::string& section) const;  // a top-level key

  struct Parsed;  // the toml++ table: job/toml_document.hpp, for the readers
  const Parsed& parsed() const { return *parsed_; }

 private:
  std::shared_ptr<const Parsed> parsed_;
};

}  // namespace treedyn
