#include "hdf5/trajectory_file.hpp"

#include "hdf5/hdf5.hpp"
#include "output/quantities.hpp"

namespace treedyn {

void write_trajectory(const std::filesystem::path& path, const Job& job,
                      const TrajectoryRecorder& recorder, const IntegrationOutcome& outcome) {
  h5::File file(path);
  const hid_t root = file.id();
  h5::write_attribute(root, "software", std::string("treedyn ") + TREEDYN_VERSION);
  h5::write_attribute(root, "job_file", job.file);
  h5::write_attribute(root, "job_text", job.text);
  h5::write_attribute(root, "title", job.title);
  h5::write_attribute(root, "method", std::string(name(job.request.settings.method)));
  h5::write_attribute(root, "parameterisation", std::string(name(job.request.parameterisation)));
  h5::write_attribute(root, "relative_tolerance", job.request.settings.relative_tolerance);
  h5::write_attribute(root, "absolute_tolerance", job.request.settings.absolute_tolerance);
  const IntegratorStats& s = outcome.stats;
  h5::write_attribute(root, "steps", static_cast<long long>(s.steps));
  h5::write_attribute(root, "rhs_evaluations", static_cast<long long>(s.rhs_evaluations));
  h5::write_attribute(root, "error_test_failures", static_cast<long long>(s.error_test_failures));
  h5::write_attribute(root, "nonlinear_convergence_failures",
                      static_cast<long long>(s.nonlinear_convergence_failures));
  h5::write_attribute(root, "chart_changes", static_cast<long long>(s.chart_changes));
  h5::write_attribute(root, "restarts", static_cast<long long>(s.restarts));
  h5::write_attribute(root, "root_evaluations", static_cast<long long>(s.root_evaluations));
  std::vector<std::string> bodies;
  for (const BodySpec& b : job.model.spec.bodies) bodies.push_back(b.name);
  h5::write_attribute(root, "bodies", bodies);

  const std::vector<double>& t = recorder.times();
  {
    h5::Handle time = h5::write_vector(root, "time", t);
    h5::write_attribute(time.id(), "units", std::string("s"));
    h5::write_attribute(time.id(), "description", std::string("output times"));
  }
  for (std::size_t k = 0; k < job.output.quantities.size(); ++k) {
    const QuantityInfo* info = find_quantity(job.output.quantities[k]);
    const auto& columns = recorder.columns(k);
    h5::Handle set = h5::write_matrix(root, std::string(info->name), recorder.values(k), t.size(),
                                      columns.size());
    h5::write_attribute(set.id(), "units", std::string(info->units));
    h5::write_attribute(set.id(), "description",
                        std::string(info->description) + "; rows: output times (/time), columns: "
                        "see the 'columns' attribute");
    h5::write_attribute(set.id(), "columns", columns);
  }
  file.commit();
}

}  // namespace treedyn
