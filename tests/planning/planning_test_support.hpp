#pragma once
// Shared fixtures of the planning tests: the interception scene, its trajectory costs (the full
// 252-trajectory grid with few precision samples, computed once per process), and helpers.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "../support/error_of.hpp"
#include "../support/paths.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/planning/interception_trial.hpp"

namespace proprio::planning::testing {

inline std::filesystem::path scene_path() { return test::data_dir() / "models" / "intercept.xml"; }

inline const robot::Arm& scene_arm() {
  static const robot::Arm arm = robot::Arm::load(scene_path());
  return arm;
}

/// The tests' scratch directories (named after the running test; see tests/support).
using proprio::test::TempDir;

/// Grid cost options with few precision samples (fast; the costs' shape is what the tests need).
inline GridCostOptions fast_grid_options() {
  GridCostOptions o;
  o.precision_samples = 6;
  o.threads = 2;
  return o;
}

inline const std::shared_ptr<const GridCostModel>& grid_model() {
  static const std::shared_ptr<const GridCostModel> model =
      std::make_shared<GridCostModel>(compute_grid_costs(scene_arm(), fast_grid_options()));
  return model;
}

inline const InterceptionSimulator& simulator() {
  static const InterceptionSimulator sim(scene_arm(), grid_model(), default_stereo_rig());
  return sim;
}

using test::error_of;  // tests/support/error_of.hpp
using test::internal_error_of;

/// Noise-free measurements of a target at frames 0..n-1, `dt` apart.
inline std::vector<PositionMeasurement> exact_measurements(const TargetMotion& target, int n,
                                                           double dt, double variance = 1e-12) {
  std::vector<PositionMeasurement> out;
  for (int i = 0; i < n; ++i) {
    const double t = i * dt;
    out.push_back({t, target.position(t), variance * Eigen::Matrix3d::Identity()});
  }
  return out;
}

}  // namespace proprio::planning::testing
