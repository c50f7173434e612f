// The whole pipeline, stage by stage.
#include "dynamics/pipeline.hpp"

namespace treedyn {

bool forward_dynamics(const Model& model, Data& data) {
  if (data.solver == AccelerationSolver::recursive) {
    compute_articulated_kinematics(model, data);
    if (!sweep_articulated_inertias(model, data)) return false;
    propagate_accelerations(model, data);
    return data.angular_acceleration.allFinite();
  }
  compute_frame_vectors(model, data);
  compute_velocity_terms(model, data);
  compute_applied_loads(model, data);
  compute_generalised_forces(model, data);
  if (!factor_mass_matrix(model, data)) return false;
  solve_angular_accelerations(model, data);
  return data.angular_acceleration.allFinite();
}

void compute_kinematics_and_loads(const Model& model, Data& data) {
  if (data.solver == AccelerationSolver::recursive) {
    compute_articulated_kinematics(model, data);
    return;
  }
  compute_frame_vectors(model, data);
  compute_applied_loads(model, data);
}

}  // namespace treedyn
