// A design's own answer for one response, beyond what every design answers
// (the mean, the exceedance, the rank measures, the failure region):
// Saltelli's Sobol' indices, Morris' elementary effects. The design computes
// it on one rank from the response table (registry_analysis.hpp lists which
// designs have one), prints its lines in the end-of-run summary, and writes
// it into /sensitivity/<response> through an AnswerWriter, which knows
// nothing of what it writes: the HDF5 layer implements the writer
// (hdf5/answer_group_writer.hpp), the design owns its datasets.
#pragma once

#include <cstddef>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "analysis/ranking.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// The datasets and attributes of one group of a design's answer.
class AnswerWriter {
 public:
  virtual ~AnswerWriter() = default;
  // One value per input or unit, labelled by `labels`, described.
  virtual void per_unit(const char* name, const std::vector<double>& values, const std::string& units,
                        const std::string& what, const std::vector<std::string>& labels) = 0;
  // Rows x (low, high), the rows named in the attribute '<row_word>s'.
  virtual void intervals(const char* name, const std::vector<double>& values, const std::string& what,
                         const std::vector<std::string>& rows, const char* row_word,
                         const std::string& units = "1") = 0;
  // The units in ranked order and what tells neighbours apart
  // (analysis/ranking.hpp); `samples_word` names what `needed` counts.
  virtual void ranking(const char* name, const ensemble::Ranking& ranking, const std::string& measure,
                       const std::vector<std::string>& units, const char* samples_word) = 0;
  // Doubles of `shape` (row-major), described; `labels` name the columns.
  virtual void array(const char* name, const std::vector<double>& values, const std::vector<std::size_t>& shape,
                     const std::string& units, const std::string& what, const std::vector<std::string>& labels) = 0;
  virtual void attribute(const char* name, const std::string& value) = 0;
  virtual void attribute(const char* name, double value) = 0;
  virtual void attribute(const char* name, long long value) = 0;
  virtual void attribute(const char* name, const std::vector<std::string>& values) = 0;
  // A group inside this one, with its description.
  virtual std::unique_ptr<AnswerWriter> group(const char* name, const std::string& description) = 0;
};

class DesignAnswer {
 public:
  virtual ~DesignAnswer() = default;
  // Its "drivers" lines in the end-of-run summary, in place of the rank
  // measures' ranking.
  virtual void print(std::ostream& out, const ensemble::EnsembleSpec& spec,
                     const ensemble::Response& response) const = 0;
  // Into the response's /sensitivity group, after the rank measures.
  virtual void write(AnswerWriter& sensitivity, const ensemble::EnsembleSpec& spec,
                     const ensemble::Response& response) const = 0;
};

}  // namespace treedyn::designs
