// Saltelli's answer in /sensitivity/<response>: first_order, total_order and
// their _ci per input (group_* and the group lists for a grouped design),
// the verdict on N as attributes, sobol_ranking, and sobol_convergence (the
// indices of the first 4, 8, ... base points).
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "designs/saltelli/saltelli_answer.hpp"

namespace treedyn::designs {
namespace {

// Per-unit values spread to the inputs: an input alone in its unit gets the
// unit's value (`width` per unit: 1, or 2 for an interval), an input of a
// larger group NaN (its own index is not estimated).
std::vector<double> per_input_values(const EnsembleSpec& spec, const std::vector<double>& unit_values,
                                     std::size_t width) {
  std::vector<double> out(spec.input_dimensions() * width, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t u = 0; u < spec.sobol_units.size(); ++u) {
    if (spec.sobol_units[u].inputs.size() != 1) continue;
    const std::size_t d = spec.sobol_units[u].inputs.front();
    for (std::size_t w = 0; w < width; ++w) out[d * width + w] = unit_values[u * width + w];
  }
  return out;
}

// The groups' indices of a grouped design, and the group list.
void write_group_indices(AnswerWriter& sg, const EnsembleSpec& spec, const SobolIndices& s) {
  const std::vector<std::string> groups = spec.unit_names(), members = spec.unit_inputs();
  sg.per_unit("group_first_order", s.first, "1", "first-order Sobol' index of each group (its inputs together)",
              groups);
  sg.per_unit("group_total_order", s.total, "1", "total Sobol' index of each group (its inputs together)", groups);
  sg.intervals("group_first_order_ci", s.first_ci, "95 % bootstrap interval of the group first-order index", groups,
               "group");
  sg.intervals("group_total_order_ci", s.total_ci, "95 % bootstrap interval of the group total index", groups, "group");
  sg.attribute("groups", groups);
  sg.attribute("group_inputs", members);
}

// Whether N is enough for the indices, and whether the blocks they rest on
// are enough of those run (attributes; see saltelli_answer.hpp).
void write_index_verdict(AnswerWriter& sg, const EnsembleSpec& spec, const SaltelliAnswer& a) {
  const IndexVerdict v = index_verdict(a.indices);
  sg.attribute("sobol_blocks", static_cast<long long>(a.blocks));
  sg.attribute("sobol_reliable", static_cast<long long>(!a.unreliable()));
  sg.attribute("index_widest_interval", v.widest);
  sg.attribute("index_widest_unit", std::isnan(v.widest) ? std::string() : spec.unit_names()[v.unit]);
  sg.attribute("index_base_points_needed", v.needed);
  sg.attribute("indices_enough", static_cast<long long>(v.enough));
}

void write_indices(AnswerWriter& sg, const EnsembleSpec& spec, const SaltelliAnswer& a) {
  const SobolIndices& s = a.indices;
  const std::vector<std::string> inputs = spec.input_names();
  auto spread = [&](const std::vector<double>& v, std::size_t width) {
    return spec.grouped ? per_input_values(spec, v, width) : v;
  };
  const std::string grouped_note = spec.grouped ? " (NaN for an input of a larger group: see group_first_order)" : "";
  sg.per_unit("first_order", spread(s.first, 1), "1",
              "first-order Sobol' index (Saltelli 2010) of each input" + grouped_note, inputs);
  sg.per_unit("total_order", spread(s.total, 1), "1",
              "total Sobol' index (Janon et al. 2014) of each input" + grouped_note, inputs);
  sg.intervals("first_order_ci", spread(s.first_ci, 2), "95 % bootstrap interval of the first-order index", inputs,
               "input");
  sg.intervals("total_order_ci", spread(s.total_ci, 2), "95 % bootstrap interval of the total index", inputs, "input");
  if (spec.grouped) write_group_indices(sg, spec, s);
  sg.attribute("sobol_variance", s.variance);
  sg.attribute("sobol_base_samples", static_cast<long long>(s.base_samples));
  sg.attribute("bootstrap_resamples", static_cast<long long>(spec.bootstrap_resamples));
  write_index_verdict(sg, spec, a);
  sg.ranking("sobol_ranking", s.ranking, "total Sobol' index", spec.unit_names(), "base points");
}

// <sg>/sobol_convergence: the indices of the first 4, 8, ... base points.
void write_sobol_convergence(AnswerWriter& sg, const EnsembleSpec& spec, const SaltelliAnswer& a) {
  const std::vector<std::string> units = spec.unit_names();
  const std::size_t k = a.convergence.size(), u = units.size();
  std::vector<double> base_points, used, first, total, first_ci, total_ci;
  for (const SobolPrefix& p : a.convergence) {
    base_points.push_back(static_cast<double>(p.base_points));
    used.push_back(static_cast<double>(p.indices.base_samples));
    first.insert(first.end(), p.indices.first.begin(), p.indices.first.end());
    total.insert(total.end(), p.indices.total.begin(), p.indices.total.end());
    first_ci.insert(first_ci.end(), p.indices.first_ci.begin(), p.indices.first_ci.end());
    total_ci.insert(total_ci.end(), p.indices.total_ci.begin(), p.indices.total_ci.end());
  }
  const std::unique_ptr<AnswerWriter> g =
      sg.group("sobol_convergence",
               "the Sobol' indices of the first m base points (their complete blocks) for "
               "m = 4, 8, 16, ... and N: a prefix of whole blocks is a Saltelli design");
  g->array("base_points", base_points, {k}, "1", "m", {});
  g->array("used", used, {k}, "1", "complete blocks among the first m", {});
  g->array("first_order", first, {k, u}, "1", "first-order index per prefix", units);
  g->array("total_order", total, {k, u}, "1", "total index per prefix", units);
  g->array("first_order_ci", first_ci, {k, u, 2}, "1",
           "95 % bootstrap interval per prefix and unit: (prefix, unit, low/high)", units);
  g->array("total_order_ci", total_ci, {k, u, 2}, "1",
           "95 % bootstrap interval per prefix and unit: (prefix, unit, low/high)", units);
}

}  // namespace

void SaltelliAnswer::write(AnswerWriter& sensitivity, const EnsembleSpec& spec, const Response&) const {
  write_indices(sensitivity, spec, *this);
  write_sobol_convergence(sensitivity, spec, *this);
}

}  // namespace treedyn::designs
