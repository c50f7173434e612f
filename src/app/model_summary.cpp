#include "app/model_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace treedyn {
namespace {

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, format, a, b, c);
  return buffer;
}

std::string body_line(const Model& m, int i) {
  return m.tree().body_name[i] + fmt("  (%.4g kg, subtree %.4g kg)", m.mass[i], m.subtree_mass[i]);
}

// The tree as text, iteratively (no recursion however deep the tree); runs of
// more than 16 single-child bodies (long chains) are shortened to their first
// and last three with a count in between. Indentation still grows at every
// branching, so a deep comb-shaped tree draws wide.
void draw_tree(std::ostream& out, const Model& m) {
  const Topology& tree = m.tree();
  struct Item {
    int body;
    std::string prefix;
    bool last;
  };
  std::vector<Item> stack{{0, "", true}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    std::vector<int> run{item.body};
    while (tree.children[run.back()].size() == 1) run.push_back(tree.children[run.back()][0]);
    std::string prefix = item.prefix;
    bool last = item.last;
    for (std::size_t k = 0; k < run.size(); ++k) {
      const bool shown = run.size() <= 16 || k < 3 || k + 3 >= run.size();
      if (shown) {
        out << prefix << (last ? "`-- " : "|-- ") << body_line(m, run[k]) << "\n";
        prefix += last ? "    " : "|   ";
        last = true;  // a single child is its parent's last
      } else if (k == 3) {
        out << prefix << "... " << run.size() - 6 << " more bodies in a chain ...\n";
      }
    }
    const auto& kids = tree.children[run.back()];
    for (std::size_t k = kids.size(); k-- > 0;) stack.push_back({kids[k], prefix, k + 1 == kids.size()});
  }
}

// A sea state's spectra, axis by axis: what the components realise of them.
void print_sea_state(std::ostream& out, const BaseMotionSpec& base, double end_time) {
  const auto* sea = std::get_if<SeaStateBase>(&base);
  if (!sea) return;
  static const char* kSpectrum[] = {"JONSWAP", "Pierson-Moskowitz", "tabulated"};
  for (int axis = 0; axis < 3; ++axis) {
    if (!sea->axes[axis]) continue;
    const SeaStateAxis& a = *sea->axes[axis];
    const SeaStateSummary s = summarize(a);
    out << "base: sea state along "
        << "xyz"[axis] << ": ";
    if (a.wave_of >= 0) {
      out << "the waves of "
          << "xyz"[a.wave_of] << fmt(" through its own RAO: the base's variance is %.6g m^2", s.base_variance)
          << fmt(" (std %.4g m)\n", std::sqrt(s.base_variance));
      continue;
    }
    out << kSpectrum[static_cast<int>(a.spectrum)];
    if (a.spectrum != WaveSpectrum::tabulated)
      out << fmt(", Hs %.6g m, Tp %.6g s", a.significant_height, a.peak_period);
    if (a.spectrum == WaveSpectrum::jonswap) out << fmt(", gamma %.4g", a.gamma);
    out << "; " << a.components() << fmt(" components on [%.6g, %.6g] Hz", a.min_frequency, a.max_frequency)
        << fmt(" (df %.4g Hz: the sea repeats every %.4g s)\n", s.df, 1.0 / s.df);
    out << fmt("  m0 = %.6g m^2 of the components, %.6g m^2 of the spectrum", s.m0_components, s.m0_spectrum)
        << fmt(" (ratio %.4f), Hs = 4 sqrt(m0) = %.6g m", s.m0_components / s.m0_spectrum,
               4.0 * std::sqrt(s.m0_components));
    if (!a.rao.empty())
      out << fmt("; through the RAO the base's variance is %.6g m^2 (std %.4g m)", s.base_variance,
                 std::sqrt(s.base_variance));
    out << "\n";
    if (end_time > 1.0 / s.df)
      out << fmt("  warning: the run (%.6g s) is longer than the sea's repeat period", end_time)
          << fmt(" (%.4g s): its motion repeats; more components over the band lengthen the period\n", 1.0 / s.df);
  }
}

}  // namespace

void print_model_summary(std::ostream& out, const Job& job) {
  const Model& m = job.model;
  if (!job.title.empty()) out << job.title << "\n";
  out << "tree (" << m.n << (m.n == 1 ? " body" : " bodies") << "):\n" << kBaseName << "\n";
  draw_tree(out, m);
  out << fmt("total mass %.6g kg\n", m.total_mass);
  print_sea_state(out, job.definition.base.kind, job.request.output_times.back());
  out << "gravity [" << m.gravity.x() << ", " << m.gravity.y() << ", " << m.gravity.z() << "] m/s^2\n";
  out << "augmented inertia K_i about the inboard joint, body frame (kg m^2):\n";
  for (int u = 0; u < m.n; ++u) {
    const int i = m.tree().regular_index[u];
    const Mat3& K = m.augmented_inertia[i];
    out << "  " << m.tree().body_name[i] << ":\n";
    for (int r = 0; r < 3; ++r) out << fmt("    [% .6e % .6e", K(r, 0), K(r, 1)) << fmt(" % .6e]\n", K(r, 2));
  }
  out << "integration: " << name(job.request.settings.method) << ", " << name(job.request.parameterisation)
      << ", solver " << name(resolve_solver(job.request.solver)) << ", rtol " << job.request.settings.relative_tolerance
      << ", atol " << job.request.settings.absolute_tolerance << "\n";
  out << "output: " << job.request.output_times.size() << " times from " << job.request.output_times.front() << " s to "
      << job.request.output_times.back() << " s; quantities:";
  for (const auto& q : job.output.quantities) out << " " << q;
  out << "\n";
}

void print_parameters(std::ostream& out, const ParameterTable& table, std::size_t at_most) {
  const auto& parameters = table.parameters();
  out << "parameters (" << parameters.size() << ", " << table.size()
      << " numbers; perturbation targets by these names, AXIS = x, y, z for a vector):\n";
  const auto nominal = table.nominal();
  for (std::size_t k = 0; k < std::min(at_most, parameters.size()); ++k) {
    const Parameter& p = parameters[k];
    out << "  " << p.name << (p.shape == ParameterShape::vector3 ? ".AXIS" : "") << " = ";
    if (p.shape == ParameterShape::scalar) {
      out << nominal[p.offset];
    } else if (p.shape == ParameterShape::list && p.size() > 6) {
      out << "[" << nominal[p.offset] << ", " << nominal[p.offset + 1] << ", ..., " << nominal[p.offset + p.size() - 1]
          << "] (" << p.size() << " entries)";
    } else {
      out << "[";
      for (int e = 0; e < p.size(); ++e) out << (e ? ", " : "") << nominal[p.offset + e];
      out << "]";
    }
    out << (p.unit == "1" ? "" : " " + p.unit) << ": " << p.enters << "\n";
  }
  if (parameters.size() > at_most)
    out << "  ... and " << parameters.size() - at_most << " more (treedyn check --parameters JOB lists them all)\n";
}

void print_run_summary(std::ostream& out, const Job& job, const Recorder& recorder, const IntegrationOutcome& outcome,
                       double wall_seconds) {
  const Model& m = job.model;
  if (recorder.empty()) return;
  const Recovered& last = recorder.last();
  out << fmt("final state at t = %.6g s:\n", last.time);
  for (int u = 0; u < m.n; ++u) {
    const Quat q = canonical_quaternion(last.rotation[u]);
    const Vec3& r = last.com_position[u];
    const Vec3& w = last.angular_velocity[u];
    out << "  " << m.tree().user_body_name(u) << fmt(": q = [%.6f, %.6f, %.6f", q.w(), q.x(), q.y())
        << fmt(", %.6f]  w = [%.5g, %.5g", q.z(), w.x(), w.y()) << fmt(", %.5g] rad/s", w.z())
        << fmt("  r = [%.5g, %.5g, %.5g] m\n", r.x(), r.y(), r.z());
  }
  const Energies& first = recorder.first_energy();
  const double e0 = first.total();
  const double scale = first.kinetic + std::abs(first.potential) + first.spring;
  out << fmt("energy: start %.10g J, end %.10g J", e0, last.energy.total())
      << fmt(", max |E - E0| %.3g J (%.3g relative)\n", recorder.max_energy_change(),
             scale > 0 ? recorder.max_energy_change() / scale : 0.0);
  if (!m.base_motion.is_fixed()) out << "  (the base moves: energy is not expected to be conserved)\n";
  const IntegratorStats& s = outcome.stats;
  out << "integrator: " << name(job.request.settings.method) << ", " << s.steps << " steps, " << s.rhs_evaluations
      << " right-hand sides, " << s.error_test_failures << " error-test failures, " << s.chart_changes
      << " chart changes" << fmt(", %.3f s wall\n", wall_seconds);
}

}  // namespace treedyn
