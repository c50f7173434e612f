#include "output/final_state.hpp"

namespace treedyn {

std::vector<std::string> final_state_columns(const Topology& tree) {
  std::vector<std::string> out;
  for (int u = 0; u < tree.n; ++u)
    for (const char* s : {"q0", "q1", "q2", "q3", "wx", "wy", "wz"}) out.push_back(tree.user_body_name(u) + "." + s);
  return out;
}

void write_final_state(const Recovered& state, std::span<double> row) {
  for (std::size_t u = 0; u < state.rotation.size(); ++u) {
    const Quat q = canonical_quaternion(state.rotation[u]);
    const Vec3& w = state.angular_velocity[u];
    double* out = row.data() + kFinalStatePerBody * u;
    out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
    out[4] = w.x(), out[5] = w.y(), out[6] = w.z();
  }
}

}  // namespace treedyn
