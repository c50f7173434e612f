#include "hdf5/trajectory_file.hpp"

#include <algorithm>

#include "output/final_state.hpp"

namespace treedyn {

void write_column_units(hid_t dataset, const ColumnLayout& layout, std::size_t quantity) {
  std::vector<std::string> units;
  for (std::size_t c = 0; c < layout.names[quantity].size(); ++c) units.push_back(column_unit(layout, quantity, c));
  if (std::any_of(units.begin(), units.end(), [&](const std::string& u) { return u != units.front(); }))
    h5::write_attribute(dataset, "column_units", units);
}

void write_quantity_datasets(hid_t group, const ColumnLayout& layout, std::size_t times,
                             std::span<const double> values, const std::string& time_path) {
  std::vector<double> block;
  for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
    const std::size_t cols = layout.names[q].size();
    block.clear();
    for (std::size_t k = 0; k < times; ++k) {
      const auto row = values.subspan(k * layout.columns + layout.offset[q], cols);
      block.insert(block.end(), row.begin(), row.end());
    }
    const QuantityInfo& info = *layout.info[q];
    h5::Handle set = h5::write_matrix(group, layout.quantity[q], block, times, cols);
    h5::write_attribute(set.id(), "units", std::string(info.units));
    h5::write_attribute(set.id(), "description",
                        std::string(info.description) + "; rows: output times (" + time_path +
                            "), columns: see the 'columns' attribute");
    h5::write_attribute(set.id(), "columns", layout.names[q]);
    write_column_units(set.id(), layout, q);
  }
}

namespace {

// Where the integrator re-expressed an orientation in a fresh chart (angle
// sets near their singular set, quaternions and direction cosines that
// drifted): time and body of each change, and the count per body.
void write_chart_changes(hid_t root, const Job& job, const IntegrationOutcome& outcome) {
  h5::Handle group = h5::create_group(root, "chart_changes");
  h5::write_attribute(group.id(), "description",
                      std::string("orientation chart changes, each at the end of an integration step "
                                  "(the integrator restarts there from its own state)"));
  std::vector<double> times;
  std::vector<long long> body, count(static_cast<std::size_t>(job.model.n), 0);
  for (const ChartChange& c : outcome.chart_changes) {
    times.push_back(c.time);
    body.push_back(c.body);
    ++count[static_cast<std::size_t>(c.body)];
  }
  {
    h5::Handle set = h5::write_vector(group.id(), "time", times);
    h5::write_attribute(set.id(), "units", std::string("s"));
    h5::write_attribute(set.id(), "description", std::string("time of each change, in time order"));
  }
  {
    const hsize_t dims[1] = {body.size()};
    h5::Handle set = h5::write_array(group.id(), "body", H5T_NATIVE_LLONG, body.data(), dims);
    h5::write_attribute(set.id(), "units", std::string("1"));
    h5::write_attribute(set.id(), "description",
                        std::string("body of each change: 0-based index into the root attribute 'bodies'"));
  }
  {
    const hsize_t dims[1] = {count.size()};
    h5::Handle set = h5::write_array(group.id(), "count", H5T_NATIVE_LLONG, count.data(), dims);
    h5::write_attribute(set.id(), "units", std::string("1"));
    h5::write_attribute(set.id(), "description", std::string("number of changes per body, in the order of 'bodies'"));
  }
}

}  // namespace

void write_trajectory(const std::filesystem::path& path, const Job& job, const Recorder& recorder,
                      const IntegrationOutcome& outcome, const RunProvenance& run,
                      const SampleOrigin* sample) {
  h5::File file(path);
  const hid_t root = file.id();
  h5::write_attribute(root, "software", std::string("treedyn ") + TREEDYN_VERSION);
  h5::write_attribute(root, "job_file", job.file);
  h5::write_attribute(root, "job_text", job.text);
  h5::write_attribute(root, "title", job.title);
  h5::write_attribute(root, "method", std::string(name(job.request.settings.method)));
  h5::write_attribute(root, "parameterisation", std::string(name(job.request.parameterisation)));
  h5::write_attribute(root, "solver", std::string(name(resolve_solver(job.request.solver))));
  h5::write_attribute(root, "relative_tolerance", job.request.settings.relative_tolerance);
  h5::write_attribute(root, "absolute_tolerance", job.request.settings.absolute_tolerance);
  for (const IntegratorStatField& f : kIntegratorStatFields)
    h5::write_attribute(root, std::string(f.name), static_cast<long long>(outcome.stats.*f.member));
  std::vector<std::string> bodies;
  for (int u = 0; u < job.model.n; ++u) bodies.push_back(job.model.tree().user_body_name(u));
  h5::write_attribute(root, "bodies", bodies);
  write_provenance(root, run);

  const std::vector<double>& t = recorder.times();
  {
    h5::Handle time = h5::write_vector(root, "time", t);
    h5::write_attribute(time.id(), "units", std::string("s"));
    h5::write_attribute(time.id(), "description", std::string("output times"));
    h5::write_attribute(time.id(), "columns", std::vector<std::string>{"time"});
  }
  write_quantity_datasets(root, recorder.layout(), t.size(), recorder.values(), "/time");
  if (!recorder.empty() && outcome.ok()) {
    std::vector<double> final_state(kFinalStatePerBody * static_cast<std::size_t>(job.model.n));
    write_final_state(recorder.last(), final_state);
    h5::Handle set = h5::write_vector(root, "final_state", final_state);
    h5::write_attribute(set.id(), "units", std::string("1, rad/s"));
    h5::write_attribute(set.id(), "description",
                        std::string("state at the last output time: per body the orientation "
                                    "quaternion (q0 >= 0) and the inertial angular velocity"));
    h5::write_attribute(set.id(), "columns", final_state_columns(job.model.tree()));
  }
  write_chart_changes(root, job, outcome);
  if (sample) {
    h5::Handle group = h5::create_group(root, "sample");
    h5::write_attribute(group.id(), "description",
                        std::string("this trajectory is one ensemble sample integrated alone "
                                    "(treedyn-ensemble --sample)"));
    h5::write_attribute(group.id(), "index", static_cast<long long>(sample->index));
    h5::write_attribute(group.id(), "status", static_cast<long long>(sample->status));
    h5::write_attribute(group.id(), "reason", sample->reason);
    h5::write_attribute(group.id(), "time_reached", sample->time_reached);
    if (!sample->inputs.empty()) {
      h5::Handle set = h5::write_vector(group.id(), "inputs", sample->inputs);
      h5::write_attribute(set.id(), "units", std::string("SI (per column: the 'column_units' attribute)"));
      h5::write_attribute(set.id(), "description",
                          std::string("the sample's sampled inputs, as in the ensemble's /samples/inputs row"));
      h5::write_attribute(set.id(), "columns", sample->input_names);
      h5::write_attribute(set.id(), "column_units", sample->input_units);
    }
  }
  file.commit();
}

}  // namespace treedyn
