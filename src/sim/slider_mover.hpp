#pragma once
// scatter without chosen objects (thesis 6.3.3): objects on rows behind the target, each sliding
// along x at its own speed and wrapping round, so that they leave the view and enter it again.

#include <functional>
#include <string>
#include <vector>

#include "proprio/core/random.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// Adds `count` sliders to the plan (ScenarioPlan::sliders and the scene's objects, instance
/// names "scatter-TYPE"), of types from `draw_type`, start places and speeds from `rng`.
void plan_sliders(int count, const std::function<std::string()>& draw_type, core::Rng& rng,
                  ScenarioPlan& plan);

class SliderMover {
 public:
  SliderMover(const World& world, const std::vector<ScenarioPlan::Slider>& sliders);
  /// Puts every slider where it is at time `t`, s.
  void move(World& world, double t) const;
  [[nodiscard]] const std::vector<ObjectId>& ids() const { return ids_; }

 private:
  std::vector<ScenarioPlan::Slider> sliders_;
  std::vector<ObjectId> ids_;
};

}  // namespace proprio::sim
