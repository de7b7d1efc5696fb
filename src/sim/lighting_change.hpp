#pragma once
// Disturbance (thesis 5.1, RecordOptions::lighting_change): half-way through the episode the main
// light jumps to another place and direction.

#include "proprio/sim/world.hpp"

namespace proprio::sim {

class LightingChange {
 public:
  /// For an episode of `total_steps` physics steps of `dt` seconds.
  LightingChange(int total_steps, double dt);
  /// From the change on, moves the light in mjData, which every step and mj_forward recompute:
  /// call it right before each render. `t` is the frame's time, s.
  void apply(World& world, double t) const;

 private:
  double at_;  // s
};

}  // namespace proprio::sim
