#pragma once
// Moving-background distractors (thesis 5.1, RecordOptions::distractors): objects that slide to
// and fro along a line behind everything else, turning as they go.

#include <string>
#include <vector>

#include "proprio/sim/scene_description.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// Where distractor number `index` of catalogue type `type` stands in the scene before the first
/// frame (instance name "distractor-TYPE"); the mover takes it onto its line from then on.
PlacedObject distractor_start(const std::string& type, int index);

class DistractorMover {
 public:
  /// The distractors of ScenarioPlan::distractors, by instance name.
  DistractorMover(const World& world, const std::vector<std::string>& names);
  /// Puts every distractor where it is at time `t`, s.
  void move(World& world, double t) const;
  [[nodiscard]] const std::vector<ObjectId>& ids() const { return ids_; }

 private:
  std::vector<ObjectId> ids_;
};

}  // namespace proprio::sim
