// A design's own answers, beyond what every design answers (the mean, the
// exceedance, the rank measures, the failure region): for one response
// (DesignAnswer: Saltelli's Sobol' indices, Morris' elementary effects), and
// for the whole run (RunAnswer: subset simulation's P and its levels). The
// design computes them on one rank from the response table
// (registry_analysis.hpp lists which designs have them), prints their lines
// in the end-of-run summary, and writes them through an AnswerWriter, which
// knows nothing of what it writes: the HDF5 layer implements the writer
// (hdf5/answer_group_writer.hpp), the design owns its datasets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "analysis/failure_region.hpp"
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
  virtual void ranking(const char* name, const analysis::Ranking& ranking, const std::string& measure,
                       const std::vector<std::string>& units, const char* samples_word) = 0;
  // Doubles of `shape` (row-major), described; `labels` name the columns.
  virtual void array(const char* name, const std::vector<double>& values, const std::vector<std::size_t>& shape,
                     const std::string& units, const std::string& what, const std::vector<std::string>& labels) = 0;
  // A scalar, described; a count's units are "1".
  virtual void value(const char* name, double value, const std::string& units, const std::string& what) = 0;
  virtual void count(const char* name, std::uint64_t value, const std::string& what) = 0;
  // A (low, high) pair of probabilities, described.
  virtual void pair(const char* name, double low, double high, const std::string& what) = 0;
  // Integers per run (a run's place in the design), described; units "1".
  virtual void column(const char* name, const std::vector<std::int32_t>& values, const std::string& what) = 0;
  virtual void column(const char* name, const std::vector<std::int64_t>& values, const std::string& what) = 0;
  // Its failure_region group: what the inputs of `which_runs` say.
  virtual void failure_region(const EnsembleSpec& spec, const analysis::FailureRegion& region,
                              const std::string& which_runs) = 0;
  virtual void attribute(const char* name, const std::string& value) = 0;
  virtual void attribute(const char* name, double value) = 0;
  virtual void attribute(const char* name, long long value) = 0;
  virtual void attribute(const char* name, const std::vector<std::string>& values) = 0;
  // A group inside this one, with its description (none when empty).
  virtual std::unique_ptr<AnswerWriter> group(const char* name, const std::string& description) = 0;
};

class DesignAnswer {
 public:
  virtual ~DesignAnswer() = default;
  // Its "drivers" lines in the end-of-run summary, in place of the rank
  // measures' ranking.
  virtual void print(std::ostream& out, const EnsembleSpec& spec, const Response& response) const = 0;
  // Into the response's /sensitivity group, after the rank measures.
  virtual void write(AnswerWriter& sensitivity, const EnsembleSpec& spec, const Response& response) const = 0;
};

// The design's answer for the whole run: why the run ended where it did, its
// lines after the responses' in the summary, its groups at the file's root
// and each run's place in the design as columns of /samples.
class RunAnswer {
 public:
  virtual ~RunAnswer() = default;
  // The file's stop_reason and the summary's.
  virtual std::string stop_reason() const = 0;
  virtual void print(std::ostream& out, const EnsembleSpec& spec) const = 0;
  // `root`: the file's root group; `samples`: /samples, whose rows
  // 0 .. rows-1 are the runs kept.
  virtual void write(AnswerWriter& root, AnswerWriter& samples, const EnsembleSpec& spec, std::size_t rows) const = 0;
};

}  // namespace treedyn::designs
