#pragma once
// Disturbance (thesis 5.1, RecordOptions::nudge_neighbour): a neighbouring object beside the push
// path is shoved sideways during the push, by something other than the arm.

#include <string>

#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_description.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// The neighbour, of catalogue type `type` (instance name "neighbour-TYPE"): beside the push
/// path toward the back, clear of the pusher, beside a target centred at x = `centre_x` with
/// footprint radius `target_r`, m.
PlacedObject place_neighbour(const std::string& type, const ObjectCatalogue& catalogue,
                             double centre_x, double target_r);

class NeighbourNudge {
 public:
  /// The object `name` (ScenarioPlan::neighbour), from where it now rests; the shove starts a
  /// fraction of the way into the arm's move, which starts at `move_start` and lasts
  /// `move_duration`, s.
  NeighbourNudge(const World& world, const std::string& name, double move_start,
                 double move_duration);
  /// Puts the neighbour where the shove has it at the frame time `t`, s, of a recording at `fps`
  /// (untouched before and after the shove).
  void apply(World& world, double t, double fps) const;

 private:
  ObjectId id_;
  Pose start_;
  double t0_;  // s
};

}  // namespace proprio::sim
