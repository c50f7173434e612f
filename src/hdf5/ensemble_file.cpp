#include "hdf5/ensemble_file.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "common/format.hpp"
#include "designs/design_rules.hpp"
#include "hdf5/answer_group_writer.hpp"
#include "hdf5/answers_file.hpp"
#include "hdf5/described.hpp"
#include "hdf5/statistics_file.hpp"
#include "hdf5/trajectory_file.hpp"
#include "output/final_state.hpp"
#include "output/motion.hpp"
#include "output/quantities.hpp"

namespace treedyn::h5 {
namespace {

std::vector<std::string> integrator_stat_columns() {
  std::vector<std::string> out;
  for (const IntegratorStatField& f : kIntegratorStatFields) out.emplace_back(f.name);
  return out;
}

}  // namespace

namespace {

// Each /samples/inputs column described, so no reader has to parse job_text.
void describe_inputs(hid_t inputs, const EnsembleSpec& spec) {
  describe(inputs, "SI (per column: the 'column_units' attribute)",
           "the sampled value of every perturbed input ([[ensemble.perturbation]] targets; "
           "orientation perturbations are rotation vectors)",
           spec.input_names());
  write_attribute(inputs, "column_units", spec.input_units());
  std::vector<std::string> target, distribution, mode;
  for (const sampling::Perturbation& p : spec.perturbations)
    for (int k = 0; k < p.dimensions(); ++k) {
      target.push_back(p.target);
      distribution.push_back(p.distribution.describe() +
                             (p.unit != 1.0 ? " x " + format_number(p.unit) + " (to " + p.si_unit + ")" : ""));
      mode.push_back(p.kind == sampling::Perturbation::Kind::orientation ? "rotation vector, composed"
                     : p.kind == sampling::Perturbation::Kind::rotation  ? "rotation, composed"
                     : p.mode == sampling::Perturbation::Mode::scale     ? "scale"
                     : p.mode == sampling::Perturbation::Mode::add       ? "add"
                                                                         : "set");
    }
  write_attribute(inputs, "column_targets", target);
  write_attribute(inputs, "column_distributions", distribution);
  write_attribute(inputs, "column_modes", mode);
  if (spec.correlations.empty()) return;
  // The correlated pairs ([[ensemble.correlation]]), so that a reader tells
  // a dependence the job asked for from one the sample happened to have.
  const std::vector<std::string> names = spec.input_names();
  std::vector<std::string> pairs;
  for (const sampling::InputCorrelation& c : spec.correlations)
    pairs.push_back(names[c.a] + " ~ " + names[c.b] + ": normal copula " + format_number(c.normal_copula) +
                    ", Spearman " + format_number(sampling::spearman_of_normal_copula(c.normal_copula)));
  write_attribute(inputs, "correlated_pairs", pairs);
}

// The /samples/responses attributes: what each column is and its limit.
void describe_responses(hid_t set, const std::vector<Response>& responses) {
  std::vector<std::string> names, units, quantity, column, reduce, fail_if;
  std::vector<double> limit, parameter;
  for (const Response& r : responses) {
    names.push_back(r.name);
    units.push_back(r.units);
    quantity.push_back(r.quantity);
    column.push_back(r.column);
    reduce.emplace_back(name(r.reduce));
    fail_if.emplace_back(name(r.fail_if));
    limit.push_back(r.has_limit() ? r.limit : std::numeric_limits<double>::quiet_NaN());
    parameter.push_back(r.reduce == Response::Reduce::at_time ? r.time
                        : r.reduce == Response::Reduce::first_time_above ||
                                r.reduce == Response::Reduce::first_time_below
                            ? r.threshold
                            : std::numeric_limits<double>::quiet_NaN());
  }
  describe(set, "per column: the 'column_units' attribute",
           "each sample's named responses ([[ensemble.response]]): one column per response; "
           "NaN when the sample failed, +inf for a level never crossed",
           names);
  write_attribute(set, "column_units", units);
  write_attribute(set, "quantity", quantity);
  write_attribute(set, "column", column);
  write_attribute(set, "reduce", reduce);
  write_attribute(set, "time_or_threshold", std::span<const double>(parameter));
  write_attribute(set, "limit", std::span<const double>(limit));
  write_attribute(set, "fail_if", fail_if);
}

std::string reduction_about(Reduction r) {
  return r == Reduction::final         ? "value at the last output time"
         : r == Reduction::min         ? "minimum over the output times"
         : r == Reduction::max         ? "maximum over the output times"
         : r == Reduction::argmin_time ? "first output time of the minimum"
                                       : "first output time of the maximum";
}

}  // namespace

EnsembleWriter::EnsembleWriter(const std::filesystem::path& path, const Job& job, const EnsembleSpec& spec,
                               const ColumnLayout& layout, std::size_t final_state_size, std::size_t unit_rows)
    : job_(job),
      spec_(spec),
      layout_(layout),
      final_size_(final_state_size),
      unit_rows_(unit_rows),
      rows_(spec, layout, final_state_size),
      file_(path) {
  samples_ = create_group(file_.id(), "samples");
  write_attribute(samples_.id(), "description", std::string(designs::rules_of(spec.design).samples_description()));
  create_sample_columns();
  create_reductions();
  if (!spec.responses.empty()) {
    const hsize_t columns[1] = {spec.responses.size()};
    responses_ = RowDataset(samples_.id(), "responses", H5T_NATIVE_DOUBLE, spec.runs, columns, unit_rows_);
    describe_responses(responses_.id(), spec.responses);
  }
  if (spec.store_trajectories > 0) create_trajectories();
  for (const ensemble::SampleRows::Dataset& d : rows_.datasets()) sample_sets_.push_back(&sample_set(d));
}

// SampleRows' dataset `d` among those created.
RowDataset& EnsembleWriter::sample_set(const ensemble::SampleRows::Dataset& d) {
  using Kind = ensemble::SampleRows::Kind;
  switch (d.kind) {
    case Kind::inputs:
      return inputs_;
    case Kind::status:
      return status_;
    case Kind::time_reached:
      return time_reached_;
    case Kind::integrator_stats:
      return integrator_stats_;
    case Kind::final_state:
      return final_state_;
    case Kind::responses:
      return responses_;
    case Kind::reduction:
      break;
  }
  return reductions_[d.reduction][d.quantity];
}

void EnsembleWriter::create_sample_columns() {
  const hid_t g = samples_.id();
  const std::size_t n = spec_.runs, d = spec_.input_dimensions();
  if (d > 0) {
    const hsize_t columns[1] = {d};
    inputs_ = RowDataset(g, "inputs", H5T_NATIVE_DOUBLE, n, columns, unit_rows_);
    describe_inputs(inputs_.id(), spec_);
  }
  // A row no record reached reads as "not run", not as the fill's 0 (ok).
  const auto not_run = static_cast<std::int32_t>(SampleStatus::not_run);
  status_ = RowDataset(g, "status", H5T_NATIVE_INT32, n, {}, unit_rows_, &not_run);
  describe(status_.id(), "1",
           "0 ok, 1 integration failed, 2 invalid model (perturbed input refused), 3 not run (a merge of an "
           "incomplete set of parts: see the root attribute held_samples; also what a row that no record "
           "reached reads as)",
           {});
  reason_ = create_string_rows(g, "reason", n, unit_rows_);
  describe(reason_.id(), "1", "why the sample failed; empty (a null string) when ok", {});
  time_reached_ = RowDataset(g, "time_reached", H5T_NATIVE_DOUBLE, n, {}, unit_rows_);
  describe(time_reached_.id(), "s", "time the integration reached (the end time when ok)", {});
  const hsize_t stat_columns[1] = {kIntegratorStatFields.size()}, final_columns[1] = {final_size_};
  integrator_stats_ = RowDataset(g, "integrator_stats", H5T_NATIVE_INT64, n, stat_columns, unit_rows_);
  describe(integrator_stats_.id(), "1", "integrator statistics per sample", integrator_stat_columns());
  final_state_ = RowDataset(g, "final_state", H5T_NATIVE_DOUBLE, n, final_columns, unit_rows_);
  describe(final_state_.id(), "1, rad/s",
           "state at the last output time: per body the orientation quaternion (q0 >= 0) and "
           "the inertial angular velocity; NaN for failed samples",
           final_state_columns(job_.model.tree()));
}

void EnsembleWriter::create_reductions() {
  for (Reduction r : spec_.per_sample) {
    const std::string about = reduction_about(r);
    const bool time = r == Reduction::argmin_time || r == Reduction::argmax_time;
    reduction_groups_.push_back(create_group(samples_.id(), std::string(name(r))));
    write_attribute(
        reduction_groups_.back().id(), "description",
        "per sample, the " + about + " of every column of every recorded quantity; NaN when the sample failed");
    reductions_.emplace_back();
    for (std::size_t q = 0; q < layout_.quantity.size(); ++q) {
      const hsize_t columns[1] = {layout_.names[q].size()};
      reductions_.back().emplace_back(reduction_groups_.back().id(), layout_.quantity[q], H5T_NATIVE_DOUBLE, spec_.runs,
                                      columns, unit_rows_);
      describe(reductions_.back().back().id(), time ? "s" : std::string(layout_.info[q]->units),
               about + " of " + layout_.quantity[q], layout_.names[q]);
      if (!time) write_column_units(reductions_.back().back().id(), layout_, q);
    }
  }
}

void EnsembleWriter::create_trajectories() {
  trajectory_group_ = create_group(file_.id(), "trajectories");
  write_attribute(trajectory_group_.id(), "description",
                  "full trajectories of samples 0 .. M-1 (store_trajectories = M): sample x "
                  "output time x column; NaN rows for samples that failed");
  const hsize_t times = job_.request.output_times.size();
  for (std::size_t q = 0; q < layout_.quantity.size(); ++q) {
    const hsize_t shape[2] = {times, layout_.names[q].size()};
    trajectories_.emplace_back(trajectory_group_.id(), layout_.quantity[q], H5T_NATIVE_DOUBLE, spec_.store_trajectories,
                               shape, 1);
    describe(trajectories_.back().id(), std::string(layout_.info[q]->units),
             std::string(layout_.info[q]->description) + "; sample x time (/stats/time) x column", layout_.names[q]);
    write_column_units(trajectories_.back().id(), layout_, q);
  }
}

std::vector<RowDataset*> EnsembleWriter::row_datasets() {
  std::vector<RowDataset*> out;
  for (RowDataset* d : {&inputs_, &status_, &time_reached_, &integrator_stats_, &final_state_, &responses_})
    if (d->exists()) out.push_back(d);
  for (auto& quantities : reductions_)
    for (RowDataset& d : quantities) out.push_back(&d);
  for (RowDataset& d : trajectories_) out.push_back(&d);
  return out;
}

void EnsembleWriter::keep_samples(std::size_t rows) {
  h5::keep_rows(reason_.id(), rows);
  for (RowDataset* d : row_datasets()) d->keep_rows(rows);
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
  file_.drop_written_pages();
}

void EnsembleWriter::write_run(const std::vector<SampleRecord>& run) {
  const std::size_t first = run.front().index, rows = run.size();
  write_reasons(run, first);
  std::vector<unsigned char> bytes;
  for (std::size_t i = 0; i < sample_sets_.size(); ++i) {
    bytes.clear();
    rows_.append(i, run, bytes);
    sample_sets_[i]->write(first, rows, bytes.data());
  }
  write_trajectories(run);
}

void EnsembleWriter::write_unit(const Unit& unit) {
  if (unit.chunks.size() != sample_sets_.size() || unit_rows_ == 0 || unit.rows != unit_rows_ ||
      unit.first % unit_rows_ != 0)
    throw IoError("HDF5: a unit of rows " + std::to_string(unit.first) + " .. " +
                  std::to_string(unit.first + unit.rows) + " is not one whole chunk of " + std::to_string(unit_rows_) +
                  " rows");
  write_reasons(unit.records, unit.first);
  for (std::size_t i = 0; i < sample_sets_.size(); ++i)
    sample_sets_[i]->write_chunk_whole(unit.first / unit_rows_, unit.chunks[i].bytes, unit.chunks[i].deflated);
  file_.drop_written_pages();
}

// Only a failed sample has a reason: the others' rows are left unwritten
// (read as empty), which spares rank 0 HDF5's conversion, a heap object
// and the deflate of a chunk of empty strings for every unit of rows.
void EnsembleWriter::write_reasons(std::span<const SampleRecord> records, std::size_t first) {
  reason_rows_.clear();
  reason_texts_.clear();
  for (std::size_t k = 0; k < records.size(); ++k)
    if (!records[k].reason.empty()) {
      reason_rows_.push_back(first + k);
      reason_texts_.push_back(records[k].reason.c_str());
    }
  write_strings_at(reason_.id(), reason_rows_, reason_texts_);
}

void EnsembleWriter::write_trajectories(const std::vector<SampleRecord>& run) {
  // Stored trajectories: one row per sample below M (NaN when it failed).
  std::vector<double> block;
  const std::size_t columns = layout_.columns;
  const std::size_t T = job_.request.output_times.size();
  for (const SampleRecord& record : run) {
    if (record.index >= spec_.store_trajectories) break;
    for (std::size_t q = 0; q < layout_.quantity.size(); ++q) {
      const std::size_t cols = layout_.names[q].size();
      block.assign(T * cols, std::numeric_limits<double>::quiet_NaN());
      if (record.trajectory.size() == T * columns)
        for (std::size_t k = 0; k < T; ++k)
          std::copy_n(record.trajectory.begin() + static_cast<long>(k * columns + layout_.offset[q]), cols,
                      block.begin() + static_cast<long>(k * cols));
      trajectories_[q].write(record.index, 1, block.data());
    }
  }
}

void EnsembleWriter::write_nominal(const std::vector<double>& trajectory) {
  Handle group = create_group(file_.id(), "nominal");
  write_attribute(group.id(), "description", std::string("the unperturbed trajectory (the job without [ensemble])"));
  const std::vector<double>& t = job_.request.output_times;
  Handle time = write_vector(group.id(), "time", t);
  describe(time.id(), "s", "output times", {"time"});
  write_quantity_datasets(group.id(), layout_, t.size(), trajectory, "/nominal/time");
  write_motion_scene(file_.id(), motion_scene(job_.definition, job_.model),
                     "the bodies' shapes and the stick figure, for viewers; the poses are /nominal/com_position and "
                     "/nominal/orientation (and /trajectories/...) when those quantities are recorded");
}

void EnsembleWriter::write_merge_origin(const std::vector<std::string>& parts,
                                        const std::vector<std::pair<std::uint64_t, std::uint64_t>>& held) {
  const hid_t root = file_.id();
  write_attribute(root, "merged_from", parts);
  std::vector<long long> flat;
  for (const auto& [first, end] : held) {
    flat.push_back(static_cast<long long>(first));
    flat.push_back(static_cast<long long>(end));
  }
  write_attribute(root, "held_samples", std::span<const long long>(flat));
}

void EnsembleWriter::write_run_answer(const designs::RunAnswer& answer, std::size_t rows) {
  GroupAnswerWriter root(file_.id()), samples(samples_.id());
  answer.write(root, samples, spec_, rows);
}

ensemble::RunSummary EnsembleWriter::complete(const std::vector<double>& nominal,
                                              const statistics::EnsembleStatistics& stats,
                                              const std::vector<analysis::ResponseAnswer>& answers,
                                              const statistics::ToleranceCheck& tolerance, ensemble::RunSummary summary,
                                              const RunProvenance& run, std::chrono::steady_clock::time_point started) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point flushing = Clock::now();
  for (RowDataset* d : row_datasets()) d->flush();
  if (!summary.writing_seconds.empty())
    summary.writing_seconds.front() += std::chrono::duration<double>(Clock::now() - flushing).count();
  write_nominal(nominal);
  write_statistics(file_.id(), job_, spec_, layout_, stats);
  write_answers(file_.id(), spec_, answers);
  write_tolerance_check(file_.id(), spec_, tolerance);
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
  finish(summary, run);
  return summary;
}

void EnsembleWriter::finish(const ensemble::RunSummary& summary, const RunProvenance& run) {
  const hid_t root = file_.id();
  write_provenance(root, run);
  write_attribute(root, "software", std::string("treedyn ") + TREEDYN_VERSION);
  write_attribute(root, "job_file", job_.file);
  write_attribute(root, "job_text", job_.text);
  write_attribute(root, "title", job_.title);
  write_attribute(root, "seed", static_cast<long long>(spec_.seed));
  write_attribute(root, "design", std::string(name(spec_.design)));
  write_attribute(root, "samples", static_cast<long long>(spec_.runs));
  write_attribute(root, "base_samples", static_cast<long long>(spec_.samples));
  for (const auto& [name, value] : designs::rules_of(spec_.design).attributes(spec_))
    std::visit([&, &name = name](const auto& v) { write_attribute(root, name, v); }, value);
  write_attribute(root, "samples_used", static_cast<long long>(summary.samples_used));
  write_attribute(root, "stop_reason", summary.stop_reason);
  write_attribute(root, "samples_ok", static_cast<long long>(summary.ok));
  write_attribute(root, "samples_failed", static_cast<long long>(summary.failed));
  write_attribute(root, "wall_time_seconds", summary.wall_seconds);
  write_attribute(root, "peak_rss_mib_per_rank", std::span<const double>(summary.peak_rss_mib));
  write_attribute(root, "samples_per_rank", std::span<const long long>(summary.samples_per_rank));
  write_attribute(root, "samples_run_here", static_cast<long long>(summary.samples_run_here()));
  write_attribute(root, "busy_seconds_per_rank", std::span<const double>(summary.busy_seconds));
  write_attribute(root, "record_writing_seconds_per_rank", std::span<const double>(summary.writing_seconds));
  write_attribute(root, "busy_cpu_seconds_per_rank", std::span<const double>(summary.busy_cpu_seconds));
  write_attribute(root, "record_writing_cpu_seconds_per_rank", std::span<const double>(summary.writing_cpu_seconds));
  write_attribute(root, "cpu_seconds_per_rank", std::span<const double>(summary.cpu_seconds));
  write_attribute(root, "unit_rows", static_cast<long long>(summary.unit_rows));
  write_attribute(root, "samples_in_units", static_cast<long long>(summary.samples_in_units));
  write_attribute(root, "unit_storing_cpu_seconds", summary.unit_storing_cpu_seconds);
  write_attribute(root, "method", std::string(name(job_.request.settings.method)));
  write_attribute(root, "parameterisation", std::string(name(job_.request.parameterisation)));
  write_attribute(root, "solver", std::string(name(resolve_solver(job_.request.solver))));
  write_attribute(root, "histogram_bins", static_cast<long long>(spec_.histogram_bins));
  write_attribute(root, "pilot_samples", static_cast<long long>(spec_.pilot_samples));
  for (RowDataset* d : row_datasets()) *d = RowDataset();
  reductions_.clear();
  reduction_groups_.clear();
  trajectories_.clear();
  for (Handle* h : {&reason_, &trajectory_group_, &samples_}) h->reset();
  file_.commit();
}

}  // namespace treedyn::h5
