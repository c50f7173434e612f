#include "job/sample_job.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "common/error.hpp"
#include "job/readers.hpp"
#include "job/toml_document.hpp"
#include "job/toml_view.hpp"
#include "model/definition.hpp"
#include "sampling/targets.hpp"

namespace treedyn {
namespace {

using Kind = sampling::Perturbation::Kind;
using Mode = sampling::Perturbation::Mode;

// A TOML float that reads back to the same double: the shortest round-trip
// digits, with ".0" where they would otherwise read as an integer.
std::string toml_float(double v) {
  std::string s = format_number(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "n": nan, inf
  return s;
}

// The line with its leading blanks removed.
std::string_view trimmed(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t");
  return first == std::string::npos ? std::string_view() : std::string_view(line).substr(first);
}

bool is_header(const std::string& line) { return trimmed(line).starts_with('['); }
bool is_comment(const std::string& line) { return trimmed(line).starts_with('#'); }

// [ensemble], [ensemble.x], [[ensemble.response]], ["ensemble"] ...
bool is_ensemble_header(const std::string& line) {
  std::string_view v = trimmed(line);
  auto skip = [&](char c) {
    while (!v.empty() && (v.front() == c || v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
  };
  if (!v.starts_with('[')) return false;
  skip('[');
  if (v.starts_with('"')) v.remove_prefix(1);
  if (!v.starts_with("ensemble")) return false;
  v.remove_prefix(8);
  if (v.starts_with('"')) v.remove_prefix(1);
  skip(' ');
  return v.starts_with('.') || v.starts_with(']');
}

// A TOML basic string.
std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// The job text without its [ensemble] tables (and the comment block just
// above each of them, which describes them).
std::string without_ensemble(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::vector<bool> keep(lines.size(), true);
  bool inside = false;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    if (is_header(lines[k])) {
      inside = is_ensemble_header(lines[k]);
      for (std::size_t j = k; inside && j > 0 && is_comment(lines[j - 1]); --j) keep[j - 1] = false;
    }
    if (inside) keep[k] = false;
  }
  std::string out;
  for (std::size_t k = 0; k < lines.size(); ++k)
    if (keep[k]) out += lines[k] + "\n";
  while (out.size() >= 2 && out.ends_with("\n\n")) out.pop_back();
  return out;
}

}  // namespace

void apply_sample_section(Job& job) {
  const TomlView root(root_table(job.document), "", job.file);
  const auto section = root.subtable("sample");
  if (!section) return;
  const TomlView& t = *section;
  t.check_keys({"index", "source", "design", "seed", "input"});
  std::vector<sampling::Perturbation> inputs;
  std::vector<double> values;
  for (const TomlView& e : t.table_array("input")) {
    e.check_keys({"target", "mode", "value"});
    sampling::Perturbation p = read_target(e, job.definition);
    if (p.kind == Kind::orientation) {
      const auto v = e.vec3("value");
      if (!v) e.fail("value", "missing required field: a rotation vector [x, y, z] in rad");
      values.insert(values.end(), {v->x(), v->y(), v->z()});
    } else if (p.kind == Kind::parameter_list) {
      if (p.mode == Mode::scale)
        e.fail("mode", "a list of phases is set or added to, not scaled; use \"set\" or \"add\"");
      const auto v = e.numbers("value");
      if (!v || static_cast<int>(v->size()) != p.entries)
        e.fail("value", "expected a list of " + std::to_string(p.entries) + " numbers in " + p.si_unit +
                            " (one per entry of " + p.target + ")");
      values.insert(values.end(), v->begin(), v->end());
    } else {
      values.push_back(e.required_number("value"));
    }
    inputs.push_back(std::move(p));
  }
  std::vector<double> parameters(job.definition.parameters.nominal().begin(),
                                 job.definition.parameters.nominal().end());
  InitialState state = job.initial;
  sampling::apply_inputs(inputs, values, job.initial, parameters, state);
  try {
    derive_model(job.definition, parameters, job.model);
  } catch (const ModelError& error) {
    t.fail("input", std::string("the sample's inputs give an invalid model: ") + error.what());
  }
  job.definition.parameters.set_nominal(parameters);
  job.initial = std::move(state);
}

Job read_sample_job(const JobDocument& document) {
  Job job = read_job(document);
  apply_sample_section(job);
  return job;
}

Job load_job(const std::filesystem::path& path) { return read_sample_job(JobDocument::read(path)); }

EnsembleJob read_ensemble_job(const JobDocument& document) {
  EnsembleJob e{read_sample_job(document), {}};
  e.spec = read_ensemble(e.job);
  return e;
}

void require_not_a_sample_job(const Job& job) {
  if (job.document.has("sample"))
    throw JobError(job.file, 0, 0, "sample",
                   "this job already is one sample of an ensemble (it has a [sample] section); "
                   "write sample jobs from the original ensemble job");
}

std::string sample_job_text(const Job& job, const EnsembleSpec& spec, std::uint64_t k, std::span<const double> inputs) {
  require_not_a_sample_job(job);
  const std::string text = without_ensemble(job.text);
  try {
    if (JobDocument::parse(text, job.file).has("ensemble")) throw std::runtime_error("still there");
  } catch (const std::exception&) {
    throw JobError(job.file, 0, 0, "ensemble",
                   "--write-job removes the [ensemble] tables by their [ensemble] / "
                   "[[ensemble.*]] headers, and this job writes its ensemble otherwise (dotted keys "
                   "or an inline table); write it with [ensemble] headers");
  }
  std::ostringstream out;
  out << text << "\n"
      << "# Sample " << k << " of the ensemble in the file 'source' below (design " << name(spec.design) << ", seed "
      << spec.seed << "),\n"
      << "# written by treedyn-ensemble --write-job " << k << ". Its sampled inputs, SI, applied to the nominal\n"
      << "# model above exactly as the ensemble applied them: `treedyn run` of this file\n"
      << "# reproduces the sample's trajectory bit for bit.\n"
      << "[sample]\n"
      << "index = " << k << "\n"
      << "source = " << toml_string(job.file) << "\n"
      << "design = \"" << name(spec.design) << "\"\n"
      << "seed = " << spec.seed << "\n";
  std::size_t d = 0;
  for (const sampling::Perturbation& p : spec.perturbations) {
    out << "\n[[sample.input]]\n"
        << "target = " << toml_string(p.target) << "\n";
    if (p.kind == Kind::parameter || p.kind == Kind::angular_velocity || p.kind == Kind::parameter_list)
      out << "mode = \"" << name_in(sampling::kModeNames, p.mode) << "\"\n";
    if (p.kind == Kind::parameter_list) {
      out << "value = [";
      for (int e = 0; e < p.entries; ++e) out << (e ? ", " : "") << toml_float(inputs[d + static_cast<std::size_t>(e)]);
      out << "]  # " << p.si_unit << ", one per entry\n";
    } else if (p.kind == Kind::orientation) {
      out << "value = [" << toml_float(inputs[d]) << ", " << toml_float(inputs[d + 1]) << ", "
          << toml_float(inputs[d + 2]) << "]  # rotation vector, rad\n";
    } else {
      out << "value = " << toml_float(inputs[d]) << "  # "
          << (p.mode == Mode::scale && p.kind != Kind::rotation ? "factor" : p.si_unit) << "\n";
    }
    d += static_cast<std::size_t>(p.dimensions());
  }
  return out.str();
}

}  // namespace treedyn
