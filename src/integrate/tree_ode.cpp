#include "integrate/tree_ode.hpp"

#include <cmath>
#include <stdexcept>

#include "dynamics/pipeline.hpp"

namespace treedyn {

TreeOde::TreeOde(const Model& model, Parameterisation parameterisation, AccelerationSolver solver)
    : model_(model),
      parameterisation_(parameterisation),
      count_(coordinate_count(parameterisation)),
      coordinate_offset_(static_cast<std::size_t>(model.n * coordinate_count(parameterisation))),
      chart_(static_cast<std::size_t>(model.n), Mat3::Identity()),
      data_(model, solver) {}

void TreeOde::pack(const InitialState& state, std::span<double> y) {
  if (static_cast<int>(state.rotation.size()) != model_.n ||
      static_cast<int>(state.angular_velocity.size()) != model_.n)
    throw std::invalid_argument("initial state: need one rotation and one angular velocity per body");
  for (int i = 0; i < model_.n; ++i) {
    const int u = model_.tree().user_index[i];
    double* q = coordinates(y, i);
    // Quaternion sign reference for recentre: +identity.
    for (int c = 0; c < count_; ++c) q[c] = c == 0 ? 1.0 : 0.0;
    chart_[i] = recentre(parameterisation_, state.rotation[u], q);
    Eigen::Map<Vec3>(y.data() + coordinate_offset_ + 3 * i) = state.angular_velocity[u];
  }
}

void TreeOde::unpack(double t, std::span<const double> y) {
  data_.time = t;
  for (int i = 0; i < model_.n; ++i) {
    data_.rotation[i].noalias() = chart_[i] * rotation_from_coordinates(parameterisation_, coordinates(y, i));
    data_.angular_velocity[i] = Eigen::Map<const Vec3>(y.data() + coordinate_offset_ + 3 * i);
  }
}

bool TreeOde::rhs(double t, std::span<const double> y, std::span<double> y_dot) {
  unpack(t, y);
  if (!forward_dynamics(model_, data_)) return false;
  for (int i = 0; i < model_.n; ++i) {
    // Body-frame angular velocity w^(i) = A_i^T w_i drives the coordinates.
    const Vec3 w_body = data_.rotation[i].transpose() * data_.angular_velocity[i];
    coordinate_rates(parameterisation_, coordinates(y, i), w_body, y_dot.data() + i * count_);
  }
  Eigen::Map<Eigen::VectorXd>(y_dot.data() + coordinate_offset_, 3 * model_.n) = data_.angular_acceleration;
  for (double v : y_dot)
    if (!std::isfinite(v)) return false;
  return true;
}

void TreeOde::chart_margins(std::span<const double> y, std::span<double> g) const {
  for (int i = 0; i < model_.n; ++i) g[i] = chart_margin(parameterisation_, coordinates(y, i));
}

int TreeOde::recentre_charts(std::span<double> y, std::span<const int> which) {
  int changed = 0;
  for (int i = 0; i < model_.n; ++i) {
    if (which[i] == 0) continue;
    double* q = coordinates(y, i);
    const Mat3 A = chart_[i] * rotation_from_coordinates(parameterisation_, q);
    chart_[i] = recentre(parameterisation_, A, q);
    ++changed;
  }
  return changed;
}

}  // namespace treedyn
