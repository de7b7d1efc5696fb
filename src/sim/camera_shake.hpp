#pragma once
// Disturbance (thesis 5.1, RecordOptions::camera_shake): the camera trembles. Each render gets
// a fresh random offset of every camera's rendered pose; calib.yml keeps the nominal pose.

#include <cstdint>
#include <vector>

#include "proprio/core/random.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

class CameraShake {
 public:
  /// Draws from a stream of `seed` of its own, so that switching it on leaves the rest alone.
  CameraShake(const World& world, std::uint64_t seed);
  /// Offsets the cameras' poses in mjData, which every step and mj_forward recompute: call it
  /// right before each render.
  void apply(World& world);

 private:
  core::Rng rng_;
  std::vector<int> camera_ids_;
};

}  // namespace proprio::sim
