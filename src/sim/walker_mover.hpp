#pragma once
// scatter with chosen objects (thesis 6.3.3, RecordOptions::scatter_objects): the objects other
// than the target wander over the table, a random walk of heading and speed, bouncing off each
// other and off the walls of a box, leaving the camera's view and coming back (or not, with
// scatter_in_view).

#include <cstdint>
#include <vector>

#include "proprio/core/random.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// Adds the walkers to the plan (ScenarioPlan::walkers, walk_min, walk_max and the scene's
/// objects, instance names "scatter-TYPE"): started at random non-overlapping places in view,
/// behind a target of footprint radius `target_r`, m, heading anywhere. The scatter objects must
/// be catalogue names. Throws Error when one is too large or they find no room.
void plan_walkers(const RecordOptions& options, const ObjectCatalogue& catalogue, double target_r,
                  core::Rng& rng, ScenarioPlan& plan);

class WalkerMover {
 public:
  /// The plan's walkers, their walk drawn from a stream of `seed` of their own.
  WalkerMover(const World& world, const ScenarioPlan& plan, std::uint64_t seed);
  /// One step of `dt` seconds of the random walk.
  void advance(double dt);
  /// Puts every walker where the walk has brought it.
  void move(World& world) const;
  [[nodiscard]] const std::vector<ObjectId>& ids() const { return ids_; }

 private:
  std::vector<ScenarioPlan::Walker> walkers_;
  std::vector<ObjectId> ids_;
  Eigen::Vector2d lo_, hi_;
  core::Rng rng_;
};

}  // namespace proprio::sim
