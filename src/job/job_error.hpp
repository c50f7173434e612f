// A job file the reader refuses: where (file, line, column), which field,
// what was wrong and what is allowed.
#pragma once

#include <stdexcept>
#include <string>

namespace treedyn {

class JobError : public std::runtime_error {
 public:
  JobError(std::string file, int line, int column, std::string field, std::string what)
      : std::runtime_error(format(file, line, column, field, what)),
        file_(std::move(file)),
        line_(line),
        column_(column),
        field_(std::move(field)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 0 when the error has no place in the file
  int column() const { return column_; }
  const std::string& field() const { return field_; }

 private:
  static std::string format(const std::string& file, int line, int column, const std::string& field,
                            const std::string& what) {
    std::string s = file;
    if (line > 0) s += ":" + std::to_string(line) + ":" + std::to_string(column);
    s += ": ";
    if (!field.empty()) s += field + ": ";
    return s + what;
  }

  std::string file_;
  int line_ = 0;
  int column_ = 0;
  std::string field_;
};

}  // namespace treedyn
