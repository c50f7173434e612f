#include "hdf5/answer_datasets.hpp"

#include <limits>
#include <string>
#include <vector>

#include "hdf5/described.hpp"

namespace treedyn::h5 {

void write_per_input(hid_t g, const char* name, const std::vector<double>& values, const std::string& units,
                     const std::string& what, const std::vector<std::string>& inputs) {
  Handle set = write_vector(g, name, values);
  describe(set.id(), units, what, inputs);
}

void write_ranking(hid_t sg, const char* name, const analysis::Ranking& ranking, const std::string& measure,
                   const std::vector<std::string>& units, const char* samples_word) {
  Handle g = create_group(sg, name);
  write_attribute(g.id(), "description",
                  "the " + std::string(name == std::string("rank_ranking") ? "inputs" : "units (inputs or groups)") +
                      " by " + measure +
                      ", largest first; neighbours in that order are told apart only where "
                      "the 95 % bootstrap interval of their difference excludes 0");
  write_attribute(g.id(), "measure", measure);
  write_attribute(g.id(), "resamples", static_cast<long long>(ranking.resamples));
  std::vector<long long> order(ranking.order.begin(), ranking.order.end());
  const hsize_t n[1] = {order.size()};
  Handle o = write_array(g.id(), "order", H5T_NATIVE_LLONG, order.data(), n);
  describe(o.id(), "1", "0-based indices into 'columns', largest " + measure + " first", {});
  write_attribute(o.id(), "columns", units);
  std::vector<long long> apart;
  for (std::size_t k = 0; k < ranking.pairs(); ++k) apart.push_back(ranking.told_apart(k) ? 1 : 0);
  const hsize_t pairs[1] = {apart.size()};
  Handle t = write_array(g.id(), "told_apart", H5T_NATIVE_LLONG, apart.data(), pairs);
  describe(t.id(), "1", "per neighbour pair (order[k], order[k + 1]): 1 where the bootstrap tells them apart", {});
  Handle d = write_matrix(g.id(), "difference_ci", ranking.difference_ci, ranking.pairs(), 2);
  describe(d.id(), "1", "per neighbour pair: 95 % bootstrap interval of the difference of their " + measure,
           {"low", "high"});
  Handle need = write_vector(g.id(), "needed", ranking.needed);
  describe(need.id(), samples_word,
           std::string("per neighbour pair not yet told apart: about the ") + samples_word +
               " that would tell it apart 4 times in 5, N ((1.96 + 0.84) sd / d)^2 (rough: d is itself "
               "uncertain); NaN once told apart, +inf for equal measures",
           {});
}

void write_interval_matrix(hid_t g, const char* name, const std::vector<double>& v, const std::string& what,
                           const std::vector<std::string>& rows, const char* row_word, const std::string& units) {
  Handle set = write_matrix(g, name, v, rows.size(), 2);
  describe(set.id(), units, what + ": " + row_word + " x (low, high); rows follow the '" + row_word + "s' attribute",
           {"low", "high"});
  write_attribute(set.id(), std::string(row_word) + "s", rows);
}

void write_pair(hid_t g, const char* name, double low, double high, const std::string& what) {
  const double values[2] = {low, high};
  const hsize_t two[1] = {2};
  Handle set = write_array(g, name, H5T_NATIVE_DOUBLE, values, two);
  describe(set.id(), "1", what, {"low", "high"});
}

void write_failure_region(hid_t parent, const EnsembleSpec& spec, const analysis::FailureRegion& region,
                          const std::string& which_runs) {
  Handle g = create_group(parent, "failure_region");
  write_attribute(g.id(), "description",
                  "the inputs of " + which_runs +
                      ", in independent standard normal space (u = Phi^-1(F(x)), "
                      "through the normal copula's inverse for correlated inputs), per input");
  write_attribute(g.id(), "runs", static_cast<long long>(region.runs));
  if (region.runs == 0 || region.mean_u.empty()) return;  // nothing beyond the limit: no numbers to show
  const std::vector<std::string> inputs = spec.input_names();
  write_per_input(g.id(), "mean_u", region.mean_u, "1", "mean of u: the design point where the region is one-sided",
                  inputs);
  write_per_input(g.id(), "mean_u2", region.mean_u2, "1", "mean of u^2: 1 for an input the failure does not select on",
                  inputs);
  write_per_input(g.id(), "divergence", region.divergence, "1",
                  "relative entropy of the failing runs' u (as a normal of their mean m and variance s^2) against "
                  "N(0, 1), (s^2 + m^2 - 1 - ln s^2) / 2; attribute 'chance': what it averages to for an input the "
                  "failure does not select on",
                  inputs);
  write_attribute(g.id(), "chance", region.chance);
  write_attribute(g.id(), "effective_runs", region.effective_runs);
  write_per_input(g.id(), "importance", region.importance, "1",
                  "max(divergence - chance, 0) as a share of its sum over the inputs", inputs);
  std::vector<std::string> unit_names, unit_inputs;
  for (const analysis::InputUnit& u : region.units) {
    unit_names.push_back(u.name);
    std::string listed;
    for (unsigned d : u.inputs) listed += (listed.empty() ? "" : ", ") + inputs[d];
    unit_inputs.push_back(listed);
  }
  write_per_input(g.id(), "unit_importance", region.unit_importance, "1",
                  "per unit (a group, a list such as a sea state's phases, or one input; attribute 'unit_inputs'): "
                  "max(sum of its inputs' divergence - their count x chance, 0) as a share of its sum over the units",
                  unit_names);
  write_attribute(g.id(), "unit_inputs", unit_inputs);
  write_per_input(g.id(), "near_bound", region.near_bound, "1",
                  "share of the failing runs within 1 % of the distribution's range of one of its bounds (NaN: "
                  "unbounded, or a full turn of an angle)",
                  inputs);
  Handle b = write_vector(g.id(), "bound", region.bound);
  describe(b.id(), "SI (per column: /samples/inputs column_units)", "the bound most of those runs are near", inputs);
  Handle x = write_vector(g.id(), "design_point", region.design_point);
  describe(x.id(), "SI (per column: /samples/inputs column_units)", "the inputs at u = mean_u", inputs);
}

}  // namespace treedyn::h5
