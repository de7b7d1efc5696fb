#pragma once
// Moving-background distractors (thesis 5.1, RecordOptions::distractors): objects that slide to
// and fro along a line behind everything else, turning as they go.

#include <string>
#include <vector>

#include "proprio/sim/backdrop.hpp"
#include "proprio/sim/scene_description.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// Where distractor number `index` of catalogue type `type` stands in the scene before the first
/// frame (instance name "distractor-TYPE"); the mover takes it onto its line from then on. With
/// layout.ghost_distractors it is felt by the table only (PlacedObject::ghost).
PlacedObject distractor_start(const std::string& type, int index,
                              const BackdropLayout& layout = recording_backdrop_layout());

class DistractorMover {
 public:
  /// The distractors of ScenarioPlan::distractors, by instance name, sliding along the line of
  /// `layout`.
  DistractorMover(const World& world, const std::vector<std::string>& names,
                  const BackdropLayout& layout = recording_backdrop_layout());
  /// Puts every distractor where it is at time `t`, s.
  void move(World& world, double t) const;
  [[nodiscard]] const std::vector<ObjectId>& ids() const { return ids_; }

 private:
  std::vector<ObjectId> ids_;
  BackdropLayout layout_;
};

}  // namespace proprio::sim
