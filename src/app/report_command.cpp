#include "app/report_command.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "analysis/answers.hpp"
#include "analysis/digest.hpp"
#include "common/exit_codes.hpp"
#include "designs/registry_analysis.hpp"
#include "hdf5/read_file.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job_error.hpp"
#include "job/sample_job.hpp"
#include "output/final_state.hpp"
#include "process/atomic_file.hpp"
#include "process/signals.hpp"

#ifndef TREEDYN_REPORT_SCRIPT
#define TREEDYN_REPORT_SCRIPT "treedyn_report.py"
#endif

extern char** environ;

namespace treedyn {
namespace {

namespace fs = std::filesystem;

// Refused files: one line, exit 2.
struct Refused {
  std::string what;
};

// The job the file was written from, read again from its job_text.
Job stored_job(const h5::ReadFile& f, const std::string& file) {
  if (!f.has_attribute("/", "job_text")) throw Refused{file + ": not a treedyn file (no job_text attribute)"};
  try {
    return read_sample_job(
        JobDocument::parse(f.string_attribute("/", "job_text"), f.string_attribute("/", "job_file")));
  } catch (const JobError& e) {
    throw Refused{file + ": its stored job no longer reads with this treedyn (" + std::string(e.what()) + ")"};
  }
}

// The ensemble summary from the file: the same digest and response lines
// treedyn-ensemble printed at the end of the run.
void ensemble_summary(std::ostream& out, const h5::ReadFile& f, const std::string& file) {
  const Job job = stored_job(f, file);
  EnsembleSpec spec;
  try {
    spec = read_ensemble(job);
  } catch (const JobError& e) {
    throw Refused{file + ": its stored [ensemble] no longer reads (" + std::string(e.what()) + ")"};
  }
  const ColumnLayout layout = column_layout(job.model, job.output);
  analysis::EnsembleDigest d;
  // The runs the file holds: fewer than `samples` (the most) when a stopping
  // rule or the design (subset simulation's last level) ended the run.
  d.samples = static_cast<std::uint64_t>(
      f.number_attribute("/", f.has_attribute("/", "samples_used") ? "samples_used" : "samples"));
  d.ok = static_cast<std::uint64_t>(f.number_attribute("/", "samples_ok"));
  d.failed = static_cast<std::uint64_t>(f.number_attribute("/", "samples_failed"));
  d.ranks = static_cast<int>(f.number_attribute("/", "ranks"));
  d.wall_seconds = f.number_attribute("/", "wall_time_seconds");
  d.run_here = f.has_attribute("/", "samples_run_here")
                   ? static_cast<std::uint64_t>(f.number_attribute("/", "samples_run_here"))
                   : d.ok + d.failed;
  const std::vector<double> t = f.doubles("/stats/time");
  if (t.empty()) throw Refused{file + ": /stats/time is empty"};
  const std::size_t T = t.size(), last = T - 1;
  d.last_time = t[last];
  const auto low = std::min_element(spec.quantiles.begin(), spec.quantiles.end());
  const auto high = std::max_element(spec.quantiles.begin(), spec.quantiles.end());
  d.low_probability = *low;
  d.high_probability = *high;
  for (auto [q, k] : analysis::digest_columns(layout, job.model.n)) {
    const std::string g = "/stats/" + layout.quantity[q] + "/";
    const std::size_t C = layout.names[q].size(), P = spec.quantiles.size();
    const std::vector<double> mean = f.doubles(g + "mean"), sd = f.doubles(g + "std"),
                              quantiles = f.doubles(g + "quantiles");
    if (mean.size() != T * C || quantiles.size() != P * T * C)
      throw Refused{file + ": " + g + " does not have the shape its job gives (an older layout?)"};
    const auto at = [&](std::size_t p) { return quantiles[(p * T + last) * C + k]; };
    d.lines.push_back({layout.quantity[q], layout.names[q][k], mean[last * C + k], sd[last * C + k],
                       at(static_cast<std::size_t>(low - spec.quantiles.begin())),
                       at(static_cast<std::size_t>(high - spec.quantiles.begin()))});
  }
  analysis::print_digest(out, d);
  if (spec.responses.empty()) return;
  if (!f.has("/responses")) {  // a merge of an incomplete set of parts: no answers
    out << "responses: not computed, the file holds only some of the samples (attribute held_samples)\n";
    return;
  }
  try {
    const ensemble::ResponseTable table = h5::response_table(f, spec.input_dimensions(), spec.responses.size());
    analysis::print_response_summary(out, spec, analysis::answer_responses(spec, table), h5::tolerance_check(f));
    if (const auto design = designs::run_answer(spec, table)) design->print(out, spec);
  } catch (const h5::IoError& e) {
    throw Refused{file + ": " + e.what()};
  }
}

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char buffer[200];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

// A trajectory file's summary: final state, energy and its drift, steps.
void trajectory_summary(std::ostream& out, const h5::ReadFile& f, const std::string& file) {
  const Job job = stored_job(f, file);
  const std::vector<double> t = f.doubles("/time");
  out << "trajectory: " << job.model.n << (job.model.n == 1 ? " body, " : " bodies, ") << t.size()
      << " output times to t = " << (t.empty() ? 0.0 : t.back()) << " s";
  if (f.has_attribute("/", "steps"))
    out << ", " << static_cast<long long>(f.number_attribute("/", "steps")) << " steps";
  out << "\n";
  if (f.has("/final_state")) {
    const std::vector<double> s = f.doubles("/final_state");
    for (int u = 0; u < job.model.n && s.size() >= kFinalStatePerBody * static_cast<std::size_t>(job.model.n); ++u) {
      const double* b = s.data() + kFinalStatePerBody * static_cast<std::size_t>(u);
      out << "  " << job.model.tree().user_body_name(u) << format(": q = [%.6f, %.6f, %.6f", b[0], b[1], b[2])
          << format(", %.6f]  w = [%.5g, %.5g", b[3], b[4], b[5]) << format(", %.5g] rad/s\n", b[6]);
    }
  }
  if (f.has("/energy")) {
    std::vector<hsize_t> dims;
    const std::vector<double> e = f.doubles("/energy", &dims);
    if (dims.size() == 2 && dims[0] > 0 && dims[1] == 4) {
      double drift = 0.0;
      for (std::size_t k = 0; k < dims[0]; ++k) drift = std::max(drift, std::abs(e[k * 4 + 3] - e[3]));
      out << format("energy: start %.10g J, end %.10g J, max |E - E0| %.3g J\n", e[3], e[(dims[0] - 1) * 4 + 3], drift);
    }
  }
}

// /usr/bin/python3 is Debian's, with python3-h5py; TREEDYN_PYTHON overrides.
std::string python() {
  if (const char* p = std::getenv("TREEDYN_PYTHON"); p && *p) return p;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

fs::path script() {
  if (const char* p = std::getenv("TREEDYN_REPORT_SCRIPT"); p && *p) return p;
  return TREEDYN_REPORT_SCRIPT;
}

int run_plotter(const std::string& file, const fs::path& out, const std::vector<std::string>& quantities) {
  std::vector<std::string> args = {python(), script().string(), file, "--out", out.string()};
  for (const auto& q : quantities) args.insert(args.end(), {"--quantity", q});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const process::SpawnAttributes attributes;  // the child gets no blocked signals
  if (posix_spawnp(&pid, argv[0], nullptr, attributes.get(), argv.data(), environ) != 0) {
    std::cerr << "error: cannot start " << args[0]
              << " for the figures: install python3 (apt-get install "
                 "python3-h5py python3-matplotlib) or set TREEDYN_PYTHON\n";
    return kExitBadInput;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return kExitInternal;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  std::cerr << "error: the plotting script was killed (signal " << WTERMSIG(status) << ")\n";
  return kExitInternal;
}

}  // namespace

int report_command(const std::string& file, std::string out_dir, const std::vector<std::string>& quantities) {
  std::ostringstream summary;
  try {
    const h5::ReadFile f(file);
    const bool ensemble = f.has("/stats") && f.has_attribute("/", "samples");
    const bool trajectory = !ensemble && f.has("/time");
    if (!ensemble && !trajectory) throw Refused{file + ": not a treedyn trajectory or ensemble file"};
    if (!f.has_attribute("/", "treedyn_version"))
      throw Refused{file + ": written by an older treedyn (before " TREEDYN_VERSION
                           ", without provenance); run its job again to report it"};
    // --quantity must name a recorded quantity: say which are.
    const Job job = stored_job(f, file);
    const ColumnLayout layout = column_layout(job.model, job.output);
    for (const std::string& q : quantities) {
      const bool derived = !ensemble && q == "joint_reaction_magnitude" && f.has("/joint_reaction");
      if (f.has(ensemble ? "/stats/" + q : "/" + q) || derived) continue;
      std::string recorded;
      for (const std::string& name : layout.quantity) recorded += " " + name;
      throw Refused{"--quantity " + q + ": not recorded in " + file + "; recorded:" + recorded};
    }
    if (ensemble) {
      if (!f.has("/samples/final") && f.has("/samples/max_over_time"))
        throw Refused{file + ": written in an older layout (/samples/max_over_time); run its job again"};
      ensemble_summary(summary, f, file);
    } else {
      trajectory_summary(summary, f, file);
    }
  } catch (const Refused& r) {
    std::cerr << "error: " << r.what << "\n";
    return kExitBadInput;
  } catch (const h5::IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  }
  std::cout << summary.str() << std::flush;  // before the script's own lines
  if (out_dir.empty()) {
    fs::path p(file);
    out_dir = (p.parent_path() / (p.stem().string() + "_report")).string();
  }
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir)) {
    std::cerr << "error: " << out_dir << ": cannot create the report directory (" << error.message() << ")\n";
    return kExitIo;
  }
  try {
    process::write_file_atomically(fs::path(out_dir) / "summary.txt", summary.str());
  } catch (const process::FileError& e) {
    std::cerr << "error: " << out_dir << ": cannot write summary.txt (" << e.what() << ")\n";
    return kExitIo;
  }
  return run_plotter(file, out_dir, quantities);
}

}  // namespace treedyn
