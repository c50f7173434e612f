// A sea state's random phases as ensemble inputs, end to end: a rod hanging
// from a heaving and swaying base (JONSWAP, 16 components per axis), its Hs
// and every phase sampled. Checks that
//   * /samples/inputs names each phase (base.z.phases[1] ...) and draws it
//     uniform on [0, 2 pi) when the job gives no distribution;
//   * /samples and /stats are bitwise the same on 1 and 3 ranks;
//   * `--write-job K` writes the phases as one list, and `treedyn run` of it
//     reproduces sample K's final state bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

constexpr int kSamples = 12, kComponents = 16;

const std::string kSeaJob = R"(title = "rod on a random sea"

[base]
type = "sea_state"
offset = [0.0, 0.0, 2.0]
phase_seed = 4

[base.z]
significant_height = 0.4
peak_period = 2.0
components = 16

[base.y]
spectrum = "pierson_moskowitz"
significant_height = 0.2
peak_period = 2.5
components = 16

[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "bryant123", angles = [20, 0, 0], unit = "deg" }

[integrator]
rtol = 1e-8
atol = 1e-10

[output]
end_time = 2.0
step = 0.1
quantities = ["orientation", "base", "energy"]

[ensemble]
samples = 12
seed = 3

[[ensemble.perturbation]]
target = "base.z.significant_height"
distribution = "uniform"
lower = 0.3
upper = 0.5

[[ensemble.perturbation]]
target = "base.z.phases"

[[ensemble.perturbation]]
target = "base.y.phases"
)";

class SeaStateEnsemble : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directory(dir_.path() / "capture");
    job_ = dir_.path() / "sea.toml";
    write_text(job_, kSeaJob);
  }
  fs::path run(int ranks) {
    const fs::path out = dir_.path() / ("sea_" + std::to_string(ranks) + ".h5");
    const CommandResult r = run_ensemble(ranks, job_, out, dir_.path() / "capture");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }
  TempDir dir_{"sea_state_ensemble_test"};
  fs::path job_;
};

TEST_F(SeaStateEnsemble, PhasesAreInputsDrawnUniformAndTheSameOnAnyRankCount) {
  const fs::path one = run(1), three = run(3);
  H5File a(one), b(three);
  ASSERT_TRUE(a.ok() && b.ok());
  const std::vector<std::string> names = read_string_attribute(a.id(), "/samples/inputs", "columns");
  ASSERT_EQ(names.size(), 1u + 2u * kComponents);
  EXPECT_EQ(names[1], "base.z.phases[1]");
  EXPECT_EQ(names[kComponents], "base.z.phases[16]");
  EXPECT_EQ(names[kComponents + 1], "base.y.phases[1]");
  const DoubleArray inputs = read_double_array(a.id(), "/samples/inputs");
  ASSERT_EQ(inputs.rows(), static_cast<std::size_t>(kSamples));
  double smallest = 10.0, largest = -1.0;
  for (std::size_t k = 0; k < inputs.rows(); ++k)
    for (std::size_t c = 1; c < inputs.cols(); ++c) {
      smallest = std::min(smallest, inputs(k, c));
      largest = std::max(largest, inputs(k, c));
    }
  // 384 uniform draws on [0, 2 pi): all inside, and they fill it (the chance that
  // none falls in the lowest or highest 5 % is 2 x 0.95^384 = 6e-9).
  EXPECT_GE(smallest, 0.0);
  EXPECT_LT(largest, 2.0 * std::numbers::pi);
  EXPECT_LT(smallest, 0.05 * 2.0 * std::numbers::pi);
  EXPECT_GT(largest, 0.95 * 2.0 * std::numbers::pi);
  for (const std::string& group : {std::string("/samples"), std::string("/stats")})
    for (const std::string& path : datasets_under(a.id(), group)) {
      const RawDataset x = read_raw(a.id(), path), y = read_raw(b.id(), path);
      EXPECT_EQ(x.dims, y.dims) << path;
      EXPECT_TRUE(x.bytes == y.bytes) << path << " differs between 1 and 3 ranks";
    }
}

TEST_F(SeaStateEnsemble, WrittenJobOfSampleKReproducesItsPhases) {
  const fs::path out = run(0);
  H5File ensemble(out);
  ASSERT_TRUE(ensemble.ok());
  const DoubleArray finals = read_double_array(ensemble.id(), "/samples/final_state");
  const std::size_t k = 7;
  const fs::path written = dir_.path() / "sample_7.toml";
  const CommandResult w =
      run_command(TREEDYN_ENSEMBLE_BINARY, {job_.string(), "--write-job", std::to_string(k), "-o", written.string()},
                  dir_.path() / "capture");
  ASSERT_EQ(w.exit_code, 0) << w.err;
  const std::string text = read_text(written);
  EXPECT_NE(text.find("target = \"base.z.phases\"\nmode = \"set\"\nvalue = ["), std::string::npos) << text;
  const fs::path rerun = dir_.path() / "rerun.h5";
  const CommandResult r =
      run_command(TREEDYN_BINARY, {"run", written.string(), "-o", rerun.string(), "-q"}, dir_.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File alone(rerun);
  ASSERT_TRUE(alone.ok());
  const std::vector<double> final_state = read_doubles(alone.id(), "/final_state");
  ASSERT_EQ(final_state.size(), finals.cols());
  EXPECT_EQ(0, std::memcmp(final_state.data(), &finals.data[k * finals.cols()], final_state.size() * sizeof(double)));
  // The phases moved the base: sample 7's final base position differs from the nominal run's.
  const fs::path nominal = dir_.path() / "nominal.h5";
  ASSERT_EQ(run_command(TREEDYN_BINARY, {"run", job_.string(), "-o", nominal.string(), "-q"}, dir_.path() / "capture")
                .exit_code,
            0);
  H5File n(nominal);
  const DoubleArray base_sample = read_double_array(alone.id(), "/base"),
                    base_nominal = read_double_array(n.id(), "/base");
  const std::size_t last = base_sample.rows() - 1;
  EXPECT_NE(base_sample(last, 2), base_nominal(last, 2));
}

}  // namespace
