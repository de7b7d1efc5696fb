#include "neighbour_nudge.hpp"

#include <algorithm>

#include "scripted_pose.hpp"

namespace proprio::sim {

namespace {

// When the shove starts, as a fraction of the arm's move: while the arm is moving, so that the
// shove is seen beside the arm's own motion.
constexpr double kStartFraction = 0.3;
constexpr double kDuration = 0.5;   // s
constexpr double kDistance = 0.05;  // m, along +y: away from the push path
constexpr double kGap = 0.03;       // m, between its footprint and the target's, in y

}  // namespace

PlacedObject place_neighbour(const std::string& type, const ObjectCatalogue& catalogue,
                             double centre_x, double target_r) {
  PlacedObject o;
  o.type = type;
  o.name = "neighbour-" + type;
  const double r = catalogue.get(type).footprint_radius();
  o.position = {centre_x, target_r + r + kGap};
  return o;
}

NeighbourNudge::NeighbourNudge(const World& world, const std::string& name, double move_start,
                               double move_duration)
    : id_(world.object(name).id),
      start_(world.object_pose(id_)),
      t0_(move_start + kStartFraction * move_duration) {}

void NeighbourNudge::apply(World& world, double t, double fps) const {
  // Half a frame's grace, so that the frame nearest the end shows the whole shove.
  if (t < t0_ || t - t0_ > kDuration + 0.5 / fps) return;
  const double u = std::min(1.0, (t - t0_) / kDuration);
  Pose p = start_;
  p.translation().y() += kDistance * u;
  p.translation().z() += kScriptedLift;
  world.set_object_pose(id_, p);
}

}  // namespace proprio::sim
