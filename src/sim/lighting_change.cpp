#include "lighting_change.hpp"

#include <Eigen/Core>

namespace proprio::sim {

namespace {

// When the light moves, as a fraction of the episode: half-way, so that about as many frames
// show each lighting.
constexpr double kAtFraction = 0.5;
// The light's new place and the point it then shines at, m, robot frame: front right and high,
// aimed at the push band, so that the shading changes all over the view.
const Eigen::Vector3d kNewPosition(0.9, -0.6, 1.0);
const Eigen::Vector3d kNewAim(0.3, 0.05, 0.0);

}  // namespace

LightingChange::LightingChange(int total_steps, double dt) : at_(kAtFraction * total_steps * dt) {}

void LightingChange::apply(World& world, double t) const {
  if (t < at_ || world.model().nlight <= 0) return;
  mjData& d = world.data();
  Eigen::Map<Eigen::Vector3d> pos(d.light_xpos);
  Eigen::Map<Eigen::Vector3d> dir(d.light_xdir);
  pos = kNewPosition;
  dir = (kNewAim - pos).normalized();
}

}  // namespace proprio::sim
