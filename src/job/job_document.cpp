#include "job/job_document.hpp"

#include "job/job_error.hpp"
#include "job/toml_document.hpp"
#include "job/toml_guard.hpp"
#include "process/atomic_file.hpp"

namespace treedyn {

JobDocument JobDocument::parse(std::string text, std::string file) {
  if (TomlGuardError guard; !guard_toml_text(text, guard))
    throw JobError(file, guard.line, guard.column, "", "not valid TOML: " + guard.message);
  auto parsed = std::make_shared<Parsed>();
  try {
    parsed->root = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw JobError(file, static_cast<int>(e.source().begin.line), static_cast<int>(e.source().begin.column), "",
                   "not valid TOML: " + std::string(e.description()));
  }
  parsed->text = std::move(text);
  parsed->file = std::move(file);
  JobDocument document;
  document.parsed_ = std::move(parsed);
  return document;
}

JobDocument JobDocument::read(const std::filesystem::path& path) {
  std::vector<char> bytes;
  try {
    bytes = process::read_file(path);
  } catch (const process::FileError&) {
    throw JobError(path.string(), 0, 0, "", "cannot open the job file for reading");
  }
  return parse(std::string(bytes.begin(), bytes.end()), path.string());
}

const std::string& JobDocument::text() const { return parsed_->text; }
const std::string& JobDocument::file() const { return parsed_->file; }
bool JobDocument::has(const std::string& section) const { return parsed_->root.contains(section); }

}  // namespace treedyn
