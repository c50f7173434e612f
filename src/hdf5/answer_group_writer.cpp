#include "hdf5/answer_group_writer.hpp"

#include "hdf5/answer_datasets.hpp"
#include "hdf5/described.hpp"

namespace treedyn::h5 {

void GroupAnswerWriter::per_unit(const char* name, const std::vector<double>& values, const std::string& units,
                                 const std::string& what, const std::vector<std::string>& labels) {
  write_per_input(group_, name, values, units, what, labels);
}

void GroupAnswerWriter::intervals(const char* name, const std::vector<double>& values, const std::string& what,
                                  const std::vector<std::string>& rows, const char* row_word,
                                  const std::string& units) {
  write_interval_matrix(group_, name, values, what, rows, row_word, units);
}

void GroupAnswerWriter::ranking(const char* name, const analysis::Ranking& ranking, const std::string& measure,
                                const std::vector<std::string>& units, const char* samples_word) {
  write_ranking(group_, name, ranking, measure, units, samples_word);
}

void GroupAnswerWriter::array(const char* name, const std::vector<double>& values,
                              const std::vector<std::size_t>& shape, const std::string& units, const std::string& what,
                              const std::vector<std::string>& labels) {
  const std::vector<hsize_t> dims(shape.begin(), shape.end());
  describe(write_array(group_, name, H5T_NATIVE_DOUBLE, values.data(), dims).id(), units, what, labels);
}

void GroupAnswerWriter::value(const char* name, double value, const std::string& units, const std::string& what) {
  write_described_scalar(group_, name, value, units, what);
}

void GroupAnswerWriter::count(const char* name, std::uint64_t value, const std::string& what) {
  write_described_scalar(group_, name, value, "1", what);
}

void GroupAnswerWriter::pair(const char* name, double low, double high, const std::string& what) {
  write_pair(group_, name, low, high, what);
}

void GroupAnswerWriter::column(const char* name, const std::vector<std::int32_t>& values, const std::string& what) {
  const hsize_t n[1] = {values.size()};
  describe(write_array(group_, name, H5T_NATIVE_INT32, values.data(), n).id(), "1", what, {});
}

void GroupAnswerWriter::column(const char* name, const std::vector<std::int64_t>& values, const std::string& what) {
  const hsize_t n[1] = {values.size()};
  describe(write_array(group_, name, H5T_NATIVE_INT64, values.data(), n).id(), "1", what, {});
}

void GroupAnswerWriter::failure_region(const EnsembleSpec& spec, const analysis::FailureRegion& region,
                                       const std::string& which_runs) {
  write_failure_region(group_, spec, region, which_runs);
}

void GroupAnswerWriter::attribute(const char* name, const std::string& value) { write_attribute(group_, name, value); }
void GroupAnswerWriter::attribute(const char* name, double value) { write_attribute(group_, name, value); }
void GroupAnswerWriter::attribute(const char* name, long long value) { write_attribute(group_, name, value); }
void GroupAnswerWriter::attribute(const char* name, const std::vector<std::string>& values) {
  write_attribute(group_, name, values);
}

std::unique_ptr<designs::AnswerWriter> GroupAnswerWriter::group(const char* name, const std::string& description) {
  Handle g = create_group(group_, name);
  if (!description.empty()) write_attribute(g.id(), "description", description);
  return std::unique_ptr<designs::AnswerWriter>(new GroupAnswerWriter(std::move(g)));
}

}  // namespace treedyn::h5
