#include "hdf5/statistics_file.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "designs/design_rules.hpp"
#include "hdf5/described.hpp"
#include "hdf5/trajectory_file.hpp"
#include "output/quantities.hpp"

namespace treedyn::h5 {
namespace {

// /stats/<quantity>: count, mean, std, sem, min, max and quantiles, time x column.
void write_quantity_statistics(hid_t qg, const Job& job, const EnsembleSpec& spec, const ColumnLayout& layout,
                               std::size_t q, const statistics::EnsembleStatistics& s) {
  const std::size_t T = job.request.output_times.size(), C = layout.columns;
  const std::size_t cols = layout.names[q].size(), offset = layout.offset[q];
  const std::string units(find_quantity(layout.quantity[q])->units);
  std::vector<double> mean, sd, sem, mn, mx;
  std::vector<std::uint64_t> count;
  std::vector<double> quantiles(spec.quantiles.size() * T * cols);
  for (std::size_t k = 0; k < T; ++k)
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t e = k * C + offset + c;
      count.push_back(s.count(e));
      mean.push_back(s.mean(e));
      sd.push_back(s.std_dev(e));
      sem.push_back(s.count(e) > 1 ? s.std_dev(e) / std::sqrt(static_cast<double>(s.count(e)))
                                   : std::numeric_limits<double>::quiet_NaN());
      mn.push_back(s.min(e));
      mx.push_back(s.max(e));
      for (std::size_t p = 0; p < spec.quantiles.size(); ++p)
        quantiles[(p * T + k) * cols + c] = s.quantile(e, spec.quantiles[p]);
    }
  const hsize_t dims2[2] = {T, cols};
  Handle cs = write_array(qg, "count", H5T_NATIVE_UINT64, count.data(), dims2);
  describe(cs.id(), "1", "number of samples in mean and std (successful samples)", layout.names[q]);
  auto matrix = [&](const char* name, const std::vector<double>& v, const std::string& what) {
    Handle set = write_matrix(qg, name, v, T, cols);
    describe(set.id(), units, what + " over the successful samples; rows: /stats/time", layout.names[q]);
    write_column_units(set.id(), layout, q);
  };
  matrix("mean", mean, "mean");
  matrix("std", sd, "sample standard deviation (n - 1)");
  matrix("sem", sem, "standard error of the mean, std / sqrt(count),");
  matrix("min", mn, "minimum");
  matrix("max", mx, "maximum");
  const hsize_t dims3[3] = {spec.quantiles.size(), T, cols};
  Handle qs = write_array(qg, "quantiles", H5T_NATIVE_DOUBLE, quantiles.data(), dims3);
  describe(qs.id(), units,
           "quantiles (probabilities in the 'probabilities' attribute) x time x column, from a "
           "histogram per entry: within one bin width of the exact sample quantile inside the "
           "histogram range",
           layout.names[q]);
  write_attribute(qs.id(), "probabilities", std::span<const double>(spec.quantiles));
}

// /stats/<quantity>/histogram: the values at the last output time, per column.
void write_final_histograms(hid_t qg, const Job& job, const ColumnLayout& layout, std::size_t q,
                            const statistics::EnsembleStatistics& s) {
  const std::size_t T = job.request.output_times.size(), C = layout.columns;
  const std::size_t cols = layout.names[q].size(), offset = layout.offset[q];
  const std::string units(find_quantity(layout.quantity[q])->units);
  const int bins = s.bins();
  Handle hg = create_group(qg, "histogram");
  write_attribute(hg.id(), "description", std::string("histogram of the values at the last output time, per column"));
  std::vector<std::uint32_t> counts;
  std::vector<std::uint64_t> under, over;
  std::vector<double> edges;
  for (std::size_t c = 0; c < cols; ++c) {
    const std::size_t e = (T - 1) * C + offset + c;
    const auto h = s.histogram(e);
    under.push_back(h[0]);
    over.push_back(h[static_cast<std::size_t>(bins + 1)]);
    counts.insert(counts.end(), h.begin() + 1, h.begin() + 1 + bins);
    for (int b = 0; b <= bins; ++b) edges.push_back(s.bin_edge(e, b));
  }
  const hsize_t hdims[2] = {cols, static_cast<hsize_t>(bins)};
  Handle hc = write_array(hg.id(), "counts", H5T_NATIVE_UINT32, counts.data(), hdims);
  describe(hc.id(), "1", "samples per bin, column x bin", layout.names[q]);
  const hsize_t edims[2] = {cols, static_cast<hsize_t>(bins + 1)};
  Handle he = write_array(hg.id(), "edges", H5T_NATIVE_DOUBLE, edges.data(), edims);
  describe(he.id(), units, "bin edges, column x (bins + 1)", layout.names[q]);
  const hsize_t udims[1] = {cols};
  Handle hu = write_array(hg.id(), "underflow", H5T_NATIVE_UINT64, under.data(), udims);
  describe(hu.id(), "1", "samples below the first edge", layout.names[q]);
  Handle ho = write_array(hg.id(), "overflow", H5T_NATIVE_UINT64, over.data(), udims);
  describe(ho.id(), "1", "samples above the last edge", layout.names[q]);
}

}  // namespace

void write_statistics(hid_t file, const Job& job, const EnsembleSpec& spec, const ColumnLayout& layout,
                      const statistics::EnsembleStatistics& s) {
  Handle group = create_group(file, "stats");
  write_attribute(group.id(), "description",
                  std::string("statistics over the successful samples at every output time; "
                              "failed samples are left out (see /samples/status)") +
                      std::string(designs::rules_of(spec.design).statistics_note()));
  const std::vector<double>& t = job.request.output_times;
  write_attribute(group.id(), "quantities", layout.quantity);  // in the job's order
  Handle time = write_vector(group.id(), "time", t);
  describe(time.id(), "s", "output times", {"time"});
  for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
    Handle qg = create_group(group.id(), layout.quantity[q]);
    write_attribute(qg.id(), "units", std::string(find_quantity(layout.quantity[q])->units));
    write_quantity_statistics(qg.id(), job, spec, layout, q, s);
    write_final_histograms(qg.id(), job, layout, q, s);
  }
}

}  // namespace treedyn::h5
