// The tree's equations as a first-order ODE y' = f(t, y) for SUNDIALS, with
// the chart bookkeeping of the orientation coordinates.
//
// y = [q_1 .. q_n, w_1 .. w_n] in the Model's regular order: each body's
// orientation coordinates (3, 4 or 9 numbers) then the inertial angular
// velocities (3 each). Orientation A_i = chart_i * R(q_i).
#pragma once

#include <span>
#include <vector>

#include "common/linalg.hpp"
#include "dynamics/data.hpp"
#include "kinematics/parameterisation.hpp"
#include "model/initial_state.hpp"
#include "model/model.hpp"

namespace treedyn {

class TreeOde {
 public:
  TreeOde(const Model& model, Parameterisation parameterisation,
          AccelerationSolver solver = AccelerationSolver::automatic);

  int size() const { return static_cast<int>(coordinate_offset_ + 3 * model_.n); }
  int charts() const { return model_.n; }  // one per body
  Parameterisation parameterisation() const { return parameterisation_; }
  const Model& model() const { return model_; }
  Data& data() { return data_; }

  // Writes y for `state` (user order), choosing a fresh chart for every body.
  void pack(const InitialState& state, std::span<double> y);
  // Rotations and angular velocities of y into data (no dynamics).
  void unpack(double t, std::span<const double> y);
  // y' = f(t, y). False on a numerical failure (non-finite state or result).
  bool rhs(double t, std::span<const double> y, std::span<double> y_dot);
  // g_i = chart_margin of body i: negative once its chart nears its singular
  // orientation (or has drifted), and must be changed.
  void chart_margins(std::span<const double> y, std::span<double> g) const;
  // Re-expresses in a fresh chart the orientation of every body i with
  // which[i] != 0. Returns how many bodies changed chart.
  int recentre_charts(std::span<double> y, std::span<const int> which);

 private:
  double* coordinates(std::span<double> y, int i) const { return y.data() + i * count_; }
  const double* coordinates(std::span<const double> y, int i) const { return y.data() + i * count_; }

  const Model& model_;
  Parameterisation parameterisation_;
  int count_;                      // coordinates per body
  std::size_t coordinate_offset_;  // n * count_
  std::vector<Mat3> chart_;        // chart base per body (regular order)
  Data data_;
};

}  // namespace treedyn
