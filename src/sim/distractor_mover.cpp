#include "distractor_mover.hpp"

#include <cmath>
#include <numbers>

#include "scripted_pose.hpp"

namespace proprio::sim {

namespace {

// The line they slide along, m: behind the target, the clutter and the scatter objects, in front
// of the backdrop (y = 0.56).
constexpr double kLineY = 0.46;
// Start places, m: x = kStartX + kStartStep * index, spread so that they do not overlap.
constexpr double kStartX = 0.15;
constexpr double kStartStep = 0.3;
// The slide, m: x = kCentreX + kAmplitude * sin(phase), across the camera's view of the table.
constexpr double kCentreX = 0.35;
constexpr double kAmplitude = 0.30;
// Slides per second, Hz: slow enough that a frame's motion is small at 25 fps.
constexpr double kFrequency = 0.15;
// Phase between one distractor and the next, cycles: half a slide, so they pass each other.
constexpr double kPhaseStep = 0.5;
// Turn, rad/s (plus the index, rad, as a start): they show their sides as they go.
constexpr double kSpin = 0.8;

}  // namespace

PlacedObject distractor_start(const std::string& type, int index) {
  PlacedObject o;
  o.type = type;
  o.name = "distractor-" + type;
  o.position = {kStartX + kStartStep * index, kLineY};
  return o;
}

DistractorMover::DistractorMover(const World& world, const std::vector<std::string>& names) {
  for (const auto& n : names) ids_.push_back(world.object(n).id);
}

void DistractorMover::move(World& world, double t) const {
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    const SceneObject& o = world.object(ids_[i]);
    const double phase =
        2.0 * std::numbers::pi * (kFrequency * t + kPhaseStep * static_cast<double>(i));
    world.set_object_pose(ids_[i], on_table(o.type, kCentreX + kAmplitude * std::sin(phase), kLineY,
                                            kSpin * t + static_cast<double>(i)));
  }
}

}  // namespace proprio::sim
