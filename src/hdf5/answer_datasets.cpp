#include "hdf5/answer_datasets.hpp"

#include <limits>

#include "hdf5/described.hpp"

namespace treedyn::answers_file {

using h5::describe;

void write_per_input(hid_t g, const char* name, const std::vector<double>& values, const std::string& units,
                     const std::string& what, const std::vector<std::string>& inputs) {
  h5::Handle set = h5::write_vector(g, name, values);
  describe(set.id(), units, what, inputs);
}

void write_ranking(hid_t sg, const char* name, const ensemble::Ranking& ranking, const std::string& measure,
                   const std::vector<std::string>& units, const char* samples_word) {
  h5::Handle g = h5::create_group(sg, name);
  h5::write_attribute(g.id(), "description",
                      "the " +
                          std::string(name == std::string("rank_ranking") ? "inputs" : "units (inputs or groups)") +
                          " by " + measure +
                          ", largest first; neighbours in that order are told apart only where "
                          "the 95 % bootstrap interval of their difference excludes 0");
  h5::write_attribute(g.id(), "measure", measure);
  h5::write_attribute(g.id(), "resamples", static_cast<long long>(ranking.resamples));
  std::vector<long long> order(ranking.order.begin(), ranking.order.end());
  const hsize_t n[1] = {order.size()};
  h5::Handle o = h5::write_array(g.id(), "order", H5T_NATIVE_LLONG, order.data(), n);
  describe(o.id(), "1", "0-based indices into 'columns', largest " + measure + " first", {});
  h5::write_attribute(o.id(), "columns", units);
  std::vector<long long> apart;
  for (std::size_t k = 0; k < ranking.pairs(); ++k) apart.push_back(ranking.told_apart(k) ? 1 : 0);
  const hsize_t pairs[1] = {apart.size()};
  h5::Handle t = h5::write_array(g.id(), "told_apart", H5T_NATIVE_LLONG, apart.data(), pairs);
  describe(t.id(), "1", "per neighbour pair (order[k], order[k + 1]): 1 where the bootstrap tells them apart", {});
  h5::Handle d = h5::write_matrix(g.id(), "difference_ci", ranking.difference_ci, ranking.pairs(), 2);
  describe(d.id(), "1", "per neighbour pair: 95 % bootstrap interval of the difference of their " + measure,
           {"low", "high"});
  h5::Handle need = h5::write_vector(g.id(), "needed", ranking.needed);
  describe(need.id(), samples_word,
           std::string("per neighbour pair not yet told apart: about the ") + samples_word +
               " that would tell it apart 4 times in 5, N ((1.96 + 0.84) sd / d)^2 (rough: d is itself "
               "uncertain); NaN once told apart, +inf for equal measures",
           {});
}

std::vector<double> per_input_values(const ensemble::EnsembleSpec& spec, const std::vector<double>& unit_values,
                                     std::size_t width) {
  std::vector<double> out(spec.input_dimensions() * width, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t u = 0; u < spec.sobol_units.size(); ++u) {
    if (spec.sobol_units[u].inputs.size() != 1) continue;
    const std::size_t d = spec.sobol_units[u].inputs.front();
    for (std::size_t w = 0; w < width; ++w) out[d * width + w] = unit_values[u * width + w];
  }
  return out;
}

void write_interval_matrix(hid_t g, const char* name, const std::vector<double>& v, const std::string& what,
                           const std::vector<std::string>& rows, const char* row_word, const std::string& units) {
  h5::Handle set = h5::write_matrix(g, name, v, rows.size(), 2);
  describe(set.id(), units, what + ": " + row_word + " x (low, high); rows follow the '" + row_word + "s' attribute",
           {"low", "high"});
  h5::write_attribute(set.id(), std::string(row_word) + "s", rows);
}

}  // namespace treedyn::answers_file
