// The HDF5 side of a design's answer (designs/design_answer.hpp): an
// AnswerWriter into one group, with the datasets every answer is written
// with (answer_datasets.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "designs/design_answer.hpp"
#include "hdf5/hdf5.hpp"

namespace treedyn::h5 {

class GroupAnswerWriter final : public designs::AnswerWriter {
 public:
  explicit GroupAnswerWriter(hid_t group) : group_(group) {}
  void per_unit(const char* name, const std::vector<double>& values, const std::string& units, const std::string& what,
                const std::vector<std::string>& labels) override;
  void intervals(const char* name, const std::vector<double>& values, const std::string& what,
                 const std::vector<std::string>& rows, const char* row_word, const std::string& units) override;
  void ranking(const char* name, const analysis::Ranking& ranking, const std::string& measure,
               const std::vector<std::string>& units, const char* samples_word) override;
  void array(const char* name, const std::vector<double>& values, const std::vector<std::size_t>& shape,
             const std::string& units, const std::string& what, const std::vector<std::string>& labels) override;
  void value(const char* name, double value, const std::string& units, const std::string& what) override;
  void count(const char* name, std::uint64_t value, const std::string& what) override;
  void pair(const char* name, double low, double high, const std::string& what) override;
  void column(const char* name, const std::vector<std::int32_t>& values, const std::string& what) override;
  void column(const char* name, const std::vector<std::int64_t>& values, const std::string& what) override;
  void failure_region(const EnsembleSpec& spec, const analysis::FailureRegion& region,
                      const std::string& which_runs) override;
  void attribute(const char* name, const std::string& value) override;
  void attribute(const char* name, double value) override;
  void attribute(const char* name, long long value) override;
  void attribute(const char* name, const std::vector<std::string>& values) override;
  std::unique_ptr<designs::AnswerWriter> group(const char* name, const std::string& description) override;

 private:
  explicit GroupAnswerWriter(Handle owned) : group_(owned.id()), owned_(std::move(owned)) {}
  hid_t group_;
  Handle owned_;  // a group this writer made (group()), closed with it
};

}  // namespace treedyn::h5
