// The HDF5 file of one trajectory (`treedyn run`), and the per-quantity
// datasets it shares with the ensemble file's nominal run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "hdf5/hdf5.hpp"
#include "hdf5/provenance.hpp"
#include "integrate/settings.hpp"
#include "job/job.hpp"
#include "output/motion.hpp"
#include "output/quantities.hpp"
#include "output/recorder.hpp"

namespace treedyn::h5 {

// A 'column_units' attribute (one unit per column) when the quantity's
// columns have mixed units (/base: m, m/s, m/s^2).
void write_column_units(hid_t dataset, const ColumnLayout& layout, std::size_t quantity);

// One (times x columns) dataset per recorded quantity under `group`, sliced
// from a recorder's flat rows, with units, description and column labels.
// `time_path` names the dataset of the rows' times, for the description.
void write_quantity_datasets(hid_t group, const ColumnLayout& layout, std::size_t times, std::span<const double> values,
                             const std::string& time_path);

// Where a trajectory came from when it is one ensemble sample rerun alone.
struct SampleOrigin {
  std::uint64_t index = 0;
  int status = 0;      // as in /samples/status: 1 when the integration failed
  std::string reason;  // why it failed
  double time_reached = 0.0;
  std::vector<std::string> input_names, input_units;
  std::vector<double> inputs;  // SI
};

// /motion without poses: the bodies' names, parents, shapes, dimensions and
// joint points, and the stick figure's segments (output/motion.hpp).
Handle write_motion_scene(hid_t root, const MotionScene& scene, const std::string& about);

// The trajectory's /motion: the scene and a Recorder of motion_output().
struct TrajectoryMotion {
  const MotionScene& scene;
  const Recorder& recorder;
};

// Writes /time, one dataset per quantity, /final_state, /motion and the
// run's attributes (and /sample for a rerun sample), under a temporary name
// renamed into place when complete. Throws IoError.
void write_trajectory(const std::filesystem::path& path, const Job& job, const Recorder& recorder,
                      const IntegrationOutcome& outcome, const RunProvenance& run, const TrajectoryMotion& motion,
                      const SampleOrigin* sample = nullptr);

}  // namespace treedyn::h5
