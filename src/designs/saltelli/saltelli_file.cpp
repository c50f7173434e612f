#include "designs/saltelli/saltelli_file.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "hdf5/answer_datasets.hpp"
#include "hdf5/described.hpp"

namespace treedyn::designs {
namespace {

using answers_file::per_input_values;  // the datasets every design's answers are written with
using answers_file::write_interval_matrix;
using answers_file::write_per_input;
using answers_file::write_ranking;
using h5::describe;

// The groups' indices of a grouped design, and the group list.
void write_group_indices(hid_t sg, const ensemble::EnsembleSpec& spec, const ensemble::SobolIndices& s) {
  const std::vector<std::string> groups = spec.unit_names(), members = spec.unit_inputs();
  write_per_input(sg, "group_first_order", s.first, "1", "first-order Sobol' index of each group (its inputs together)",
                  groups);
  write_per_input(sg, "group_total_order", s.total, "1", "total Sobol' index of each group (its inputs together)",
                  groups);
  write_interval_matrix(sg, "group_first_order_ci", s.first_ci,
                        "95 % bootstrap interval of the group first-order index", groups, "group");
  write_interval_matrix(sg, "group_total_order_ci", s.total_ci, "95 % bootstrap interval of the group total index",
                        groups, "group");
  h5::write_attribute(sg, "groups", groups);
  h5::write_attribute(sg, "group_inputs", members);
}

// Whether N is enough for the indices, and whether the blocks they rest on
// are enough of those run (attributes; see analysis/answers.hpp).
void write_index_verdict(hid_t sg, const ensemble::EnsembleSpec& spec, const ensemble::ResponseAnswer& a) {
  const ensemble::SobolIndices& s = *a.sobol;
  const ensemble::IndexVerdict v = ensemble::index_verdict(s);
  h5::write_attribute(sg, "sobol_blocks", static_cast<long long>(a.sobol_blocks));
  h5::write_attribute(sg, "sobol_reliable",
                      static_cast<long long>(static_cast<double>(s.base_samples) >=
                                             ensemble::kReliableBlockShare * static_cast<double>(a.sobol_blocks)));
  h5::write_attribute(sg, "index_widest_interval", v.widest);
  h5::write_attribute(sg, "index_widest_unit", std::isnan(v.widest) ? std::string() : spec.unit_names()[v.unit]);
  h5::write_attribute(sg, "index_base_points_needed", v.needed);
  h5::write_attribute(sg, "indices_enough", static_cast<long long>(v.enough));
}

void write_indices(hid_t sg, const ensemble::EnsembleSpec& spec, const ensemble::ResponseAnswer& a) {
  const ensemble::SobolIndices& s = *a.sobol;
  const std::vector<std::string> inputs = spec.input_names();
  auto spread = [&](const std::vector<double>& v, std::size_t width) {
    return spec.grouped ? per_input_values(spec, v, width) : v;
  };
  const std::string grouped_note = spec.grouped ? " (NaN for an input of a larger group: see group_first_order)" : "";
  write_per_input(sg, "first_order", spread(s.first, 1), "1",
                  "first-order Sobol' index (Saltelli 2010) of each input" + grouped_note, inputs);
  write_per_input(sg, "total_order", spread(s.total, 1), "1",
                  "total Sobol' index (Janon et al. 2014) of each input" + grouped_note, inputs);
  write_interval_matrix(sg, "first_order_ci", spread(s.first_ci, 2), "95 % bootstrap interval of the first-order index",
                        inputs, "input");
  write_interval_matrix(sg, "total_order_ci", spread(s.total_ci, 2), "95 % bootstrap interval of the total index",
                        inputs, "input");
  if (spec.grouped) write_group_indices(sg, spec, s);
  h5::write_attribute(sg, "sobol_variance", s.variance);
  h5::write_attribute(sg, "sobol_base_samples", static_cast<long long>(s.base_samples));
  h5::write_attribute(sg, "bootstrap_resamples", static_cast<long long>(spec.bootstrap_resamples));
  write_index_verdict(sg, spec, a);
  write_ranking(sg, "sobol_ranking", s.ranking, "total Sobol' index", spec.unit_names(), "base points");
}

// <sg>/sobol_convergence: the indices of the first 1, 2, 4, ... base points.
void write_sobol_convergence(hid_t sg, const ensemble::EnsembleSpec& spec, const ensemble::ResponseAnswer& a) {
  const std::vector<std::string> units = spec.unit_names();
  const std::size_t k = a.sobol_convergence.size(), u = units.size();
  std::vector<double> base_points, used, first, total, first_ci, total_ci;
  for (const ensemble::SobolPrefix& p : a.sobol_convergence) {
    base_points.push_back(static_cast<double>(p.base_points));
    used.push_back(static_cast<double>(p.indices.base_samples));
    first.insert(first.end(), p.indices.first.begin(), p.indices.first.end());
    total.insert(total.end(), p.indices.total.begin(), p.indices.total.end());
    first_ci.insert(first_ci.end(), p.indices.first_ci.begin(), p.indices.first_ci.end());
    total_ci.insert(total_ci.end(), p.indices.total_ci.begin(), p.indices.total_ci.end());
  }
  h5::Handle g = h5::create_group(sg, "sobol_convergence");
  h5::write_attribute(g.id(), "description",
                      std::string("the Sobol' indices of the first m base points (their complete blocks) for "
                                  "m = 1, 2, 4, ... and N: a prefix of whole blocks is a Saltelli design"));
  describe(h5::write_vector(g.id(), "base_points", base_points).id(), "1", "m", {});
  describe(h5::write_vector(g.id(), "used", used).id(), "1", "complete blocks among the first m", {});
  describe(h5::write_matrix(g.id(), "first_order", first, k, u).id(), "1", "first-order index per prefix", units);
  describe(h5::write_matrix(g.id(), "total_order", total, k, u).id(), "1", "total index per prefix", units);
  const hsize_t shape[3] = {k, u, 2};
  describe(h5::write_array(g.id(), "first_order_ci", H5T_NATIVE_DOUBLE, first_ci.data(), shape).id(), "1",
           "95 % bootstrap interval per prefix and unit: (prefix, unit, low/high)", units);
  describe(h5::write_array(g.id(), "total_order_ci", H5T_NATIVE_DOUBLE, total_ci.data(), shape).id(), "1",
           "95 % bootstrap interval per prefix and unit: (prefix, unit, low/high)", units);
}

}  // namespace

void write_sobol(hid_t sg, const ensemble::EnsembleSpec& spec, const ensemble::ResponseAnswer& a) {
  write_indices(sg, spec, a);
  write_sobol_convergence(sg, spec, a);
}

}  // namespace treedyn::designs
