#include "dynamics/data.hpp"

namespace treedyn {

Data::Data(const Model& model, AccelerationSolver requested) : solver(resolve_solver(requested)) {
  const auto n = static_cast<std::size_t>(model.n);
  rotation.assign(n, Mat3::Identity());
  angular_velocity.assign(n, Vec3::Zero());
  com_to_inboard_joint.assign(n, Vec3::Zero());
  if (solver == AccelerationSolver::sparse_ldlt) {
    mass_matrix = SparseMassMatrix(model.tree());
    augmented_inertia.assign(n, Mat3::Zero());
    barycentre_to_inboard.assign(n, Vec3::Zero());
    branch_d.assign(n, Vec3::Zero());
    centripetal_b.assign(n, Vec3::Zero());
    subtree_centripetal_b.assign(n, Vec3::Zero());
    ancestor_centripetal_d.assign(n, Vec3::Zero());
    generalised_force = Eigen::VectorXd::Zero(3 * model.n);
  } else {
    articulated = ArticulatedBodies(model.n);
  }
  force.assign(n, Vec3::Zero());
  subtree_force.assign(n, Vec3::Zero());
  moment.assign(n, Vec3::Zero());
  joint_moment.assign(n, Vec3::Zero());
  spring_energy.assign(n, 0.0);
  angular_acceleration = Eigen::VectorXd::Zero(3 * model.n);
}

}  // namespace treedyn
