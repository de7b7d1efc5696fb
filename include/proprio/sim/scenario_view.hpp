#pragma once
// One picture of a scenario's scene, as the first camera sees it before anything moves (what
// `proprio sim view` writes): a quick look at a scene file or a seed's placement.

#include <opencv2/core.hpp>

#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/recorder.hpp"

namespace proprio::sim {

/// Plans the scenario of `options`, builds its world, lets it settle for `settle_steps` physics
/// steps and renders the first camera (BGR, options.width x options.height; shadows as
/// options.shadows). Throws Error for a bad option or scene file.
cv::Mat render_scenario_view(const RecordOptions& options, const ObjectCatalogue& catalogue,
                             int settle_steps = 50);

}  // namespace proprio::sim
