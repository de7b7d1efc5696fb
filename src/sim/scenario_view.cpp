#include "proprio/sim/scenario_view.hpp"

#include "proprio/sim/renderer.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

cv::Mat render_scenario_view(const RecordOptions& options, const ObjectCatalogue& catalogue,
                             int settle_steps) {
  const ScenarioPlan plan = plan_scenario(options, catalogue);
  World world = build_scenario_world(plan, catalogue, options);
  world.step(settle_steps);
  RenderOptions ropt;
  ropt.shadows = options.shadows;
  Renderer renderer(world, ropt);
  return renderer.rgb(world, world.camera_names().at(0));
}

}  // namespace proprio::sim
