#include "model/initial_state.hpp"

namespace treedyn {

void turn_body_frame_spins(const InitialState& nominal, InitialState& state) {
  for (std::size_t u = 0; u < nominal.body_frame_spin.size(); ++u) {
    const std::optional<Vec3>& spin = nominal.body_frame_spin[u];
    if (spin && state.rotation[u] != nominal.rotation[u]) state.angular_velocity[u] = state.rotation[u] * *spin;
  }
}

}  // namespace treedyn
