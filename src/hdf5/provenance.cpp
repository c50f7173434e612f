#include "hdf5/provenance.hpp"

#include <Eigen/Core>
#include <libdeflate.h>
#include <sundials/sundials_config.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "common/hash.hpp"
#include "common/host_time.hpp"
#include "hdf5/hdf5.hpp"

#ifndef TREEDYN_GIT_COMMIT
#define TREEDYN_GIT_COMMIT "unknown"
#endif
#ifndef TREEDYN_BUILD_TYPE
#define TREEDYN_BUILD_TYPE "unknown"
#endif
#ifndef TREEDYN_COMPILER
#define TREEDYN_COMPILER "unknown"
#endif

namespace treedyn::h5 {
namespace {

// A word as a shell would need it to mean the same.
std::string shell_word(const std::string& word) {
  if (!word.empty() &&
      word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=:,+@%") ==
          std::string::npos)
    return word;
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string number(int v) { return std::to_string(v); }

}  // namespace

RunProvenance start_provenance(int argc, const char* const* argv, const std::string& job_path) {
  RunProvenance p;
  p.start_utc = utc_now();
  p.host = host_name();
  for (int k = 0; k < argc; ++k) p.command_line += (k ? " " : "") + shell_word(argv[k]);
  std::error_code error;
  const auto absolute = std::filesystem::absolute(job_path, error);
  p.job_path = error ? job_path : absolute.lexically_normal().string();
  return p;
}

void write_provenance(hid_t root, const RunProvenance& run) {
  write_attribute(root, "start_utc", run.start_utc);
  write_attribute(root, "end_utc", utc_now());
  write_attribute(root, "host", run.host);
  write_attribute(root, "command_line", run.command_line);
  write_attribute(root, "job_path", run.job_path);
  write_attribute(root, "treedyn_version", std::string(TREEDYN_VERSION));
  write_attribute(root, "git_commit", std::string(TREEDYN_GIT_COMMIT));
  write_attribute(root, "build_type", std::string(TREEDYN_BUILD_TYPE));
  write_attribute(root, "compiler", std::string(TREEDYN_COMPILER));
  write_attribute(root, "sundials_version", std::string(SUNDIALS_VERSION));
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  write_attribute(root, "hdf5_version",
                  std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(release));
  write_attribute(root, "libdeflate_version", std::string(LIBDEFLATE_VERSION_STRING));
  write_attribute(root, "eigen_version",
                  number(EIGEN_WORLD_VERSION) + "." + number(EIGEN_MAJOR_VERSION) + "." + number(EIGEN_MINOR_VERSION));
  write_attribute(root, "tomlplusplus_version",
                  number(TOML_LIB_MAJOR) + "." + number(TOML_LIB_MINOR) + "." + number(TOML_LIB_PATCH));
  write_attribute(root, "mpi_library", run.mpi_library.empty() ? std::string("none (serial)") : run.mpi_library);
  write_attribute(root, "ranks", static_cast<long long>(run.ranks));
  if (!run.rank_hosts.empty()) write_attribute(root, "rank_hosts", run.rank_hosts);
}

std::string build_identity() {
  // The commit is fixed at configure time, so an edited and rebuilt tree
  // keeps it: the executable's own bytes tell builds apart.
  static const std::string identity = [] {
    std::ifstream exe("/proc/self/exe", std::ios::binary);
    StreamingHash h;
    char buffer[1 << 16];
    while (exe.read(buffer, sizeof buffer) || exe.gcount() > 0)
      h.update({buffer, static_cast<std::size_t>(exe.gcount())});
    return std::string("treedyn ") + TREEDYN_VERSION + ", commit " + TREEDYN_GIT_COMMIT + ", " + TREEDYN_BUILD_TYPE +
           ", " + TREEDYN_COMPILER + ", executable " + hex64(h.digest());
  }();
  return identity;
}

}  // namespace treedyn::h5
