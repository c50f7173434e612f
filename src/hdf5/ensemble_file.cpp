#include "hdf5/ensemble_file.hpp"

#include <algorithm>

#include "hdf5/trajectory_file.hpp"
#include "output/final_state.hpp"
#include "output/quantities.hpp"

namespace treedyn {
namespace {

using ensemble::SampleRecord;

void describe(hid_t set, const std::string& units, const std::string& description,
              const std::vector<std::string>& columns) {
  h5::write_attribute(set, "units", units);
  h5::write_attribute(set, "description", description);
  if (!columns.empty()) h5::write_attribute(set, "columns", columns);
}

std::vector<std::string> integrator_stat_columns() {
  std::vector<std::string> out;
  for (const IntegratorStatField& f : kIntegratorStatFields) out.emplace_back(f.name);
  return out;
}

}  // namespace

EnsembleWriter::EnsembleWriter(const std::filesystem::path& path, const Job& job,
                               const ensemble::EnsembleSpec& spec,
                               const ColumnLayout& layout, std::size_t final_state_size)
    : job_(job), spec_(spec), layout_(layout), final_size_(final_state_size), file_(path) {
  const std::size_t n = spec.samples;
  const std::size_t chunk = std::max<std::size_t>(spec.block_size * 16, 64);
  samples_ = h5::create_group(file_.id(), "samples");
  const hid_t g = samples_.id();
  h5::write_attribute(g, "description",
                      std::string("one row per sample, by sample index 0 .. samples-1"));
  const std::size_t d = spec.input_dimensions();
  if (d > 0) {
    inputs_ = h5::create_rows(g, "inputs", H5T_NATIVE_DOUBLE, n, d, chunk);
    describe(inputs_.id(), "SI (per column: the 'column_units' attribute)",
             "the sampled value of every perturbed input ([[ensemble.perturbation]] targets; "
             "orientation perturbations are rotation vectors)",
             spec.input_names());
    std::vector<std::string> units;
    for (const ensemble::Perturbation& p : spec.perturbations)
      for (int k = 0; k < p.dimensions(); ++k) units.push_back(p.mode == ensemble::Perturbation::Mode::scale ? "1" : p.si_unit);
    h5::write_attribute(inputs_.id(), "column_units", units);
  }
  status_ = h5::create_rows(g, "status", H5T_NATIVE_INT32, n, 0, chunk);
  describe(status_.id(), "1", "0 ok, 1 integration failed, 2 invalid model (perturbed input refused)", {});
  reason_ = h5::create_string_rows(g, "reason", n, kReasonLength, chunk);
  describe(reason_.id(), "1", "why the sample failed; empty when ok", {});
  time_reached_ = h5::create_rows(g, "time_reached", H5T_NATIVE_DOUBLE, n, 0, chunk);
  describe(time_reached_.id(), "s", "time the integration reached (the end time when ok)", {});
  integrator_stats_ = h5::create_rows(g, "integrator_stats", H5T_NATIVE_INT64, n,
                                      kIntegratorStatFields.size(), chunk);
  describe(integrator_stats_.id(), "1", "integrator statistics per sample", integrator_stat_columns());
  final_state_ = h5::create_rows(g, "final_state", H5T_NATIVE_DOUBLE, n, final_state_size, chunk);
  describe(final_state_.id(), "1, rad/s",
           "state at the last output time: per body the orientation quaternion (q0 >= 0) and "
           "the inertial angular velocity; NaN for failed samples",
           final_state_columns(job.model.tree()));
  max_group_ = h5::create_group(g, "max_over_time");
  h5::write_attribute(max_group_.id(), "description",
                      std::string("per sample, the maximum over the output times of every column of "
                                  "every recorded quantity"));
  for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
    max_.push_back(h5::create_rows(max_group_.id(), layout.quantity[q], H5T_NATIVE_DOUBLE, n,
                                   layout.names[q].size(), chunk));
    describe(max_.back().id(), std::string(find_quantity(layout.quantity[q])->units),
             "maximum over time of " + layout.quantity[q], layout.names[q]);
  }
}

void EnsembleWriter::write_records(std::vector<SampleRecord> records) {
  std::sort(records.begin(), records.end(),
            [](const SampleRecord& a, const SampleRecord& b) { return a.index < b.index; });
  std::vector<SampleRecord> run;
  for (SampleRecord& r : records) {
    if (!run.empty() && r.index != run.back().index + 1) {
      write_run(run);
      run.clear();
    }
    run.push_back(std::move(r));
  }
  if (!run.empty()) write_run(run);
}

void EnsembleWriter::write_run(const std::vector<SampleRecord>& run) {
  const std::size_t first = run.front().index, rows = run.size();
  const std::size_t d = spec_.input_dimensions();
  std::vector<double> inputs, times, finals;
  std::vector<std::int32_t> status;
  std::vector<std::int64_t> stats;
  std::vector<std::string> reasons;
  for (const SampleRecord& r : run) {
    std::vector<double> in = r.inputs;
    in.resize(d, std::numeric_limits<double>::quiet_NaN());
    inputs.insert(inputs.end(), in.begin(), in.end());
    times.push_back(r.time_reached);
    status.push_back(static_cast<std::int32_t>(r.status));
    for (const IntegratorStatField& f : kIntegratorStatFields) stats.push_back(r.stats.*f.member);
    reasons.push_back(r.reason);
    finals.insert(finals.end(), r.final_state.begin(), r.final_state.end());
  }
  if (d > 0) h5::write_rows(inputs_.id(), H5T_NATIVE_DOUBLE, first, rows, d, inputs.data());
  h5::write_rows(status_.id(), H5T_NATIVE_INT32, first, rows, 0, status.data());
  h5::write_string_rows(reason_.id(), first, reasons, kReasonLength);
  h5::write_rows(time_reached_.id(), H5T_NATIVE_DOUBLE, first, rows, 0, times.data());
  h5::write_rows(integrator_stats_.id(), H5T_NATIVE_INT64, first, rows, kIntegratorStatFields.size(),
                 stats.data());
  h5::write_rows(final_state_.id(), H5T_NATIVE_DOUBLE, first, rows, final_size_, finals.data());
  for (std::size_t q = 0; q < layout_.quantity.size(); ++q) {
    const std::size_t cols = layout_.names[q].size();
    std::vector<double> block;
    for (const SampleRecord& r : run) {
      const auto begin = r.max_over_time.begin() + static_cast<long>(layout_.offset[q]);
      block.insert(block.end(), begin, begin + static_cast<long>(cols));
    }
    h5::write_rows(max_[q].id(), H5T_NATIVE_DOUBLE, first, rows, cols, block.data());
  }
}

void EnsembleWriter::write_nominal(const std::vector<double>& trajectory) {
  h5::Handle group = h5::create_group(file_.id(), "nominal");
  h5::write_attribute(group.id(), "description",
                      std::string("the unperturbed trajectory (the job without [ensemble])"));
  const std::vector<double>& t = job_.request.output_times;
  h5::Handle time = h5::write_vector(group.id(), "time", t);
  describe(time.id(), "s", "output times", {});
  write_quantity_datasets(group.id(), layout_, t.size(), trajectory, "/nominal/time");
}

void EnsembleWriter::write_statistics(const ensemble::EnsembleStatistics& s) {
  h5::Handle group = h5::create_group(file_.id(), "stats");
  h5::write_attribute(group.id(), "description",
                      std::string("statistics over the successful samples at every output time; "
                                  "failed samples are left out (see /samples/status)"));
  const std::vector<double>& t = job_.request.output_times;
  h5::Handle time = h5::write_vector(group.id(), "time", t);
  describe(time.id(), "s", "output times", {});
  const std::size_t T = t.size(), C = layout_.columns;
  const int bins = s.bins();
  for (std::size_t q = 0; q < layout_.quantity.size(); ++q) {
    const std::size_t cols = layout_.names[q].size(), offset = layout_.offset[q];
    const std::string units(find_quantity(layout_.quantity[q])->units);
    h5::Handle qg = h5::create_group(group.id(), layout_.quantity[q]);
    h5::write_attribute(qg.id(), "units", units);
    std::vector<double> mean, sd, mn, mx;
    std::vector<std::uint64_t> count;
    std::vector<double> quantiles(spec_.quantiles.size() * T * cols);
    for (std::size_t k = 0; k < T; ++k)
      for (std::size_t c = 0; c < cols; ++c) {
        const std::size_t e = k * C + offset + c;
        count.push_back(s.count(e));
        mean.push_back(s.mean(e));
        sd.push_back(s.std_dev(e));
        mn.push_back(s.min(e));
        mx.push_back(s.max(e));
        for (std::size_t p = 0; p < spec_.quantiles.size(); ++p)
          quantiles[(p * T + k) * cols + c] = s.quantile(e, spec_.quantiles[p]);
      }
    const hsize_t dims2[2] = {T, cols};
    h5::Handle cs = h5::write_array(qg.id(), "count", H5T_NATIVE_UINT64, count.data(), dims2);
    describe(cs.id(), "1", "number of samples in mean and std (successful samples)", layout_.names[q]);
    auto matrix = [&](const char* name, const std::vector<double>& v, const std::string& what) {
      h5::Handle set = h5::write_matrix(qg.id(), name, v, T, cols);
      describe(set.id(), units, what + " over the successful samples; rows: /stats/time", layout_.names[q]);
    };
    matrix("mean", mean, "mean");
    matrix("std", sd, "sample standard deviation (n - 1)");
    matrix("min", mn, "minimum");
    matrix("max", mx, "maximum");
    const hsize_t dims3[3] = {spec_.quantiles.size(), T, cols};
    h5::Handle qs = h5::write_array(qg.id(), "quantiles", H5T_NATIVE_DOUBLE, quantiles.data(), dims3);
    describe(qs.id(), units,
             "quantiles (probabilities in the 'probabilities' attribute) x time x column, from a "
             "histogram per entry: within one bin width of the exact sample quantile inside the "
             "histogram range",
             layout_.names[q]);
    h5::write_attribute(qs.id(), "probabilities", std::span<const double>(spec_.quantiles));

    // Histograms of the final values.
    h5::Handle hg = h5::create_group(qg.id(), "histogram");
    h5::write_attribute(hg.id(), "description",
                        std::string("histogram of the values at the last output time, per column"));
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
    h5::Handle hc = h5::write_array(hg.id(), "counts", H5T_NATIVE_UINT32, counts.data(), hdims);
    describe(hc.id(), "1", "samples per bin, column x bin", layout_.names[q]);
    const hsize_t edims[2] = {cols, static_cast<hsize_t>(bins + 1)};
    h5::Handle he = h5::write_array(hg.id(), "edges", H5T_NATIVE_DOUBLE, edges.data(), edims);
    describe(he.id(), units, "bin edges, column x (bins + 1)", layout_.names[q]);
    const hsize_t udims[1] = {cols};
    h5::Handle hu = h5::write_array(hg.id(), "underflow", H5T_NATIVE_UINT64, under.data(), udims);
    describe(hu.id(), "1", "samples below the first edge", layout_.names[q]);
    h5::Handle ho = h5::write_array(hg.id(), "overflow", H5T_NATIVE_UINT64, over.data(), udims);
    describe(ho.id(), "1", "samples above the last edge", layout_.names[q]);
  }
}

void EnsembleWriter::finish(const EnsembleSummary& summary) {
  const hid_t root = file_.id();
  h5::write_attribute(root, "software", std::string("treedyn ") + TREEDYN_VERSION);
  h5::write_attribute(root, "job_file", job_.file);
  h5::write_attribute(root, "job_text", job_.text);
  h5::write_attribute(root, "title", job_.title);
  h5::write_attribute(root, "seed", static_cast<long long>(spec_.seed));
  h5::write_attribute(root, "design", std::string(ensemble::name(spec_.design)));
  h5::write_attribute(root, "samples", static_cast<long long>(spec_.samples));
  h5::write_attribute(root, "samples_ok", static_cast<long long>(summary.ok));
  h5::write_attribute(root, "samples_failed", static_cast<long long>(summary.failed));
  h5::write_attribute(root, "ranks", static_cast<long long>(summary.ranks));
  h5::write_attribute(root, "wall_time_seconds", summary.wall_seconds);
  h5::write_attribute(root, "peak_rss_mib_per_rank", std::span<const double>(summary.peak_rss_mib));
  h5::write_attribute(root, "samples_per_rank", std::span<const double>(summary.samples_per_rank));
  h5::write_attribute(root, "busy_seconds_per_rank", std::span<const double>(summary.busy_seconds));
  h5::write_attribute(root, "method", std::string(name(job_.request.settings.method)));
  h5::write_attribute(root, "parameterisation", std::string(name(job_.request.parameterisation)));
  h5::write_attribute(root, "histogram_bins", static_cast<long long>(spec_.histogram_bins));
  h5::write_attribute(root, "pilot_samples", static_cast<long long>(spec_.pilot_samples));
  for (h5::Handle* h : {&inputs_, &status_, &reason_, &time_reached_, &integrator_stats_,
                        &final_state_, &max_group_, &samples_})
    h->reset();
  max_.clear();
  file_.commit();
}

}  // namespace treedyn
