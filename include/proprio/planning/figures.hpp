#pragma once
// The figures of thesis 3.5-3.7 as images (BGR, drawn with OpenCV): the energy over the
// trajectory grid (Fig 3-8), an interception seen from above with the prediction's growing
// uncertainty (Fig 3-10), and the interception point chosen as the noise grows, per prior
// (Fig 3-11).

#include <opencv2/core.hpp>
#include <vector>

#include "proprio/planning/interception_planner.hpp"
#include "proprio/planning/interception_trial.hpp"
#include "proprio/planning/trajectory_grid.hpp"

namespace proprio::planning {

/// The target of the figures: it crosses the workspace from p0 + (0.10, 0.12, 0) m, reached at the
/// earliest interception (t_plan + the move's duration), to p0 + (-0.05, 0.12, 0) m 1.5 s later
/// (0.1 m/s along -x), so it stays within reach for the planner's whole default window and the
/// choice of time is the planner's to make.
TargetMotion figure_target(const GridSpec& grid, double t_plan);

/// Fig 3-8: one heat map of the total energy (eq 3.41, N m s) per gamma of the grid, theta across
/// and l up, on a shared colour scale with a colour bar. Invalid points are dark grey. Throws
/// Error when no point is valid.
cv::Mat draw_energy_grid(const GridCosts& costs);

/// Fig 3-10: a recorded trial (TrialOptions::record) from above, world x across and y up (m):
/// the grid's end points (the reachable half-disc), the target's true path, its measurements,
/// the first plan's predicted positions with circles of radius equal to their predicted std (so
/// that they grow with the prediction), the arm's commanded and executed paths, and the target
/// and the end-effector at the interception. Throws Error when the trial was not recorded.
cv::Mat draw_interception(const TrialResult& trial, const GridSpec& grid);

/// One point of Fig 3-11: where the planner chose to meet the target at one noise level and
/// prior (means over repeated noise draws on the same target).
struct NoiseChoice {
  double noise_cm = 0;
  PriorMode mode = PriorMode::kBoth;
  double mean_time = 0;  ///< interception minus first plan, s
  double std_time = 0;   ///< over the draws, s
  int draws = 0;         ///< draws with a feasible plan
};

/// Fig 3-11: left, the target's path from above with the mean chosen interception point per
/// noise level and prior (the marker grows with the noise); right, the interception time after
/// the plan against the noise, one line per prior with +-1 std bars.
cv::Mat draw_noise_choices(const TargetMotion& target, double t_plan, const GridSpec& grid,
                           const std::vector<NoiseChoice>& choices);

}  // namespace proprio::planning
