#include "distractor_mover.hpp"

#include <cmath>
#include <numbers>

#include "scripted_pose.hpp"

namespace proprio::sim {

namespace {

// Start places, m: x = kStartX + kStartStep * index, spread so that they do not overlap.
constexpr double kStartX = 0.15;
constexpr double kStartStep = 0.3;
// Slides per second, Hz: slow enough that a frame's motion is small at 25 fps.
constexpr double kFrequency = 0.15;
// Phase between one distractor and the next, cycles: half a slide, so they pass each other.
constexpr double kPhaseStep = 0.5;
// Turn, rad/s (plus the index, rad, as a start): they show their sides as they go.
constexpr double kSpin = 0.8;

}  // namespace

// The line they slide along (BackdropLayout::line_y; the recorder's: behind the target, the
// clutter and the scatter objects, in front of the backdrop) and the slide x = centre_x +
// amplitude * sin(phase), across the camera's view of the table.

PlacedObject distractor_start(const std::string& type, int index, const BackdropLayout& layout) {
  PlacedObject o;
  o.type = type;
  o.name = "distractor-" + type;
  o.position = {kStartX + kStartStep * index, layout.line_y};
  o.ghost = layout.ghost_distractors;
  return o;
}

DistractorMover::DistractorMover(const World& world, const std::vector<std::string>& names,
                                 const BackdropLayout& layout)
    : layout_(layout) {
  for (const auto& n : names) ids_.push_back(world.object(n).id);
}

void DistractorMover::move(World& world, double t) const {
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    const SceneObject& o = world.object(ids_[i]);
    const double phase =
        2.0 * std::numbers::pi * (kFrequency * t + kPhaseStep * static_cast<double>(i));
    world.set_object_pose(ids_[i],
                          on_table(o.type, layout_.centre_x + layout_.amplitude * std::sin(phase),
                                   layout_.line_y, kSpin * t + static_cast<double>(i)));
  }
}

}  // namespace proprio::sim
