// The trajectory grid (eqs 3.37-3.40), its costs from inverse dynamics (eqs 3.41-3.43), the
// versioned cache, and the interpolated cost model.
#include "proprio/planning/trajectory_grid.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "planning_test_support.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/robot/dynamics.hpp"

namespace proprio::planning {
namespace {
using testing::error_of;
using testing::scene_arm;
using testing::TempDir;

GridCostOptions tiny_options() {
  GridCostOptions o;
  o.grid.theta = {-1.0, 1.0, 2};
  o.grid.length = {0.08, 0.18, 2};
  o.grid.gamma = {-0.2, 0.2, 2};
  o.precision_samples = 8;
  o.threads = 1;
  return o;
}

TEST(TrajectoryGrid, TheThesisGridHas252Trajectories) {
  const GridSpec g;
  EXPECT_EQ(g.size(), 252);
  EXPECT_EQ(g.index(5, 6, 5), 251);
  const robot::TrajectoryParams p = g.params(g.index(2, 3, 4));
  EXPECT_NEAR(p.theta, -1.5 + 0.6 * 2, 1e-12);
  EXPECT_NEAR(p.length, 0.07 + 0.14 * 3 / 6, 1e-12);
  EXPECT_NEAR(p.gamma, -0.3 + 0.12 * 4, 1e-12);
  // End point relative to the start (SPEC section 2), and the trajectory ends there.
  const Eigen::Vector3d p2 = g.end_point(p);
  EXPECT_NEAR((p2 - g.start).norm(), p.length, 1e-12);
  EXPECT_LT((g.trajectory(p).sample(g.duration).position - p2).norm(), 1e-12);
  GridSpec bad;
  bad.length.min = 0;
  EXPECT_NE(error_of([&] { bad.validate(); }).find("lengths"), std::string::npos);
}

TEST(TrajectoryGrid, EveryTrajectoryOfTheDefaultGridIsTrackable) {
  const GridCosts& c = testing::grid_model()->costs();
  EXPECT_EQ(c.summary.valid, 252);
  for (const GridPoint& p : c.points) {
    EXPECT_TRUE(p.valid) << p.why_invalid;
    EXPECT_GT(p.energy, 0);
    EXPECT_GT(p.rho, 0);
    EXPECT_NEAR(p.energy, p.energy_per_joint.sum(), 1e-9);
  }
  // c of eq 3.43: the median trajectory gets the perturbation's variance.
  EXPECT_NEAR(c.sigma_scale / c.summary.median_rho, 0.005 * 0.005, 1e-15);
}

TEST(TrajectoryGrid, EnergyIsTheInverseDynamicsIntegral) {
  const GridCostOptions o = tiny_options();
  const GridCosts c = compute_grid_costs(scene_arm(), o);
  ASSERT_EQ(c.summary.valid, 8);
  // Recompute one point by hand: track, mj_inverse, eq 3.41.
  robot::ArmState state(scene_arm());
  const robot::JointVector q0 =
      solve_scheduled(state, o.grid.start, scene_arm().clamp(robot::JointVector::Zero()), o.motion)
          .q;
  const GridPoint& p = c.points[5];
  const robot::TrackResult track =
      track_scheduled(state, o.grid.trajectory(p.psi), q0, o.rate_hz, o.motion);
  const robot::Energy e =
      robot::energy(robot::inverse_dynamics(state, track.joints), track.joints.dt);
  EXPECT_NEAR(p.energy, e.total, 1e-12);
  EXPECT_EQ(p.samples_used, 8);
}

TEST(TrajectoryGrid, CostsDoNotDependOnTheThreadCount) {
  GridCostOptions o = tiny_options();
  const GridCosts one = compute_grid_costs(scene_arm(), o);
  o.threads = 3;
  const GridCosts three = compute_grid_costs(scene_arm(), o);
  EXPECT_EQ(one.key, three.key);
  for (std::size_t i = 0; i < one.points.size(); ++i) {
    EXPECT_EQ(one.points[i].energy, three.points[i].energy);
    EXPECT_EQ(one.points[i].rho, three.points[i].rho);
  }
}

TEST(TrajectoryGrid, UnreachableEndPointsAreMarkedNotNaN) {
  GridCostOptions o = tiny_options();
  o.grid.start = {0.40, 0.0, 0.05};
  o.grid.length = {0.05, 0.30, 2};  // 0.7 m from the base: out of reach
  const GridCosts c = compute_grid_costs(scene_arm(), o);
  EXPECT_GT(c.summary.invalid, 0);
  for (const GridPoint& p : c.points) {
    if (!p.valid) {
      EXPECT_FALSE(p.why_invalid.empty());
    }
    EXPECT_TRUE(std::isfinite(p.energy) && std::isfinite(p.rho));
  }
  o.grid.start = {2.0, 0.0, 0.05};
  EXPECT_NE(error_of([&] { compute_grid_costs(scene_arm(), o); }).find("start point"),
            std::string::npos);
}

TEST(TrajectoryGridCache, RoundTripsAndInvalidatesOnChange) {
  TempDir tmp("proprio_planning_");
  const auto file = tmp.path() / "grid.json";
  GridCostOptions o = tiny_options();
  const GridCosts a = load_or_compute_grid_costs(scene_arm(), o, file);
  EXPECT_NE(a.summary.source.find("computed"), std::string::npos);
  ASSERT_TRUE(std::filesystem::exists(file));
  const GridCosts b = load_or_compute_grid_costs(scene_arm(), o, file);
  EXPECT_EQ(b.summary.source, "cache");
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].energy, b.points[i].energy);
    EXPECT_EQ(a.points[i].rho, b.points[i].rho);
    EXPECT_EQ(a.points[i].rho_per_joint, b.points[i].rho_per_joint);
  }
  EXPECT_EQ(a.sigma_scale, b.sigma_scale);
  // A different grid or a different arm model gives another key and a recomputation.
  o.grid.gamma.max = 0.25;
  EXPECT_NE(grid_cache_key(scene_arm(), o), a.key);
  const GridCosts c = load_or_compute_grid_costs(scene_arm(), o, file);
  EXPECT_NE(c.summary.source.find("stale"), std::string::npos);
  const robot::Arm standalone =
      robot::Arm::load(test::data_dir() / "models" / "arm_standalone.xml");
  EXPECT_NE(grid_cache_key(standalone, tiny_options()),
            grid_cache_key(scene_arm(), tiny_options()));
  // The thread count is not part of the key.
  GridCostOptions t = tiny_options();
  t.threads = 7;
  EXPECT_EQ(grid_cache_key(scene_arm(), t), grid_cache_key(scene_arm(), tiny_options()));
}

TEST(TrajectoryGridCache, BadFilesAreErrorsNamingTheFile) {
  TempDir tmp("proprio_planning_");
  const auto file = tmp.path() / "grid.json";
  const GridCosts good = compute_grid_costs(scene_arm(), tiny_options());
  write_grid_costs(file, good);
  const std::string text = core::read_file(file);
  auto expect_error = [&](const std::string& contents, const std::string& what) {
    const auto bad = tmp.path() / "bad.json";
    core::write_file_atomic(bad, contents);
    const std::string e = error_of([&] { read_grid_costs(bad); });
    EXPECT_NE(e.find("bad.json"), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  expect_error(text.substr(0, text.size() / 2), "bad.json");  // truncated
  core::Json j = core::read_json(file);
  j["format"] = "something.else";
  expect_error(j.dump(), "format");
  j = core::read_json(file);
  j["format_version"] = 99;
  expect_error(j.dump(), "format_version 99");
  j = core::read_json(file);
  j["points"].erase(0);
  expect_error(j.dump(), "grid points");
  j = core::read_json(file);
  j["points"][2]["energy"] = "NaN";
  expect_error(j.dump(), "energy");
  j = core::read_json(file);
  j["points"][1]["rho_per_joint"] = {1, 2};
  expect_error(j.dump(), "rho_per_joint");
  // An unreadable cache is replaced, not fatal.
  core::write_file_atomic(file, "{ not json");
  const GridCosts c = load_or_compute_grid_costs(scene_arm(), tiny_options(), file);
  EXPECT_NE(c.summary.source.find("unreadable"), std::string::npos);
  EXPECT_EQ(read_grid_costs(file).key, good.key);
}

TEST(GridCostModel, InterpolatesTheGridValuesAndClamps) {
  const GridCostModel& m = *testing::grid_model();
  const GridSpec& g = m.grid();
  for (int i : {0, 17, 100, 251}) {
    const GridPoint& p = m.costs().points[static_cast<std::size_t>(i)];
    const Eigen::Vector3d psi(p.psi.theta, p.psi.length, p.psi.gamma);
    EXPECT_NEAR(m.log_energy(psi), std::log(p.energy), 1e-9);
    EXPECT_NEAR(m.log_rho(psi), std::log(p.rho), 1e-9);
    EXPECT_NEAR(m.arm_variance(psi), m.costs().sigma_scale / p.rho, 1e-12);
  }
  const Eigen::Vector3d outside(5.0, 1.0, -2.0);
  EXPECT_EQ(m.clamp(outside), Eigen::Vector3d(g.theta.max, g.length.max, g.gamma.min));
  EXPECT_EQ(m.log_energy(outside), m.log_energy(m.clamp(outside)));
  // Between grid points the value stays between its neighbours' range (smooth, no blow-up).
  const Eigen::Vector3d mid(0.15, 0.1, 0.05);
  EXPECT_TRUE(std::isfinite(m.log_energy(mid)));
}

TEST(GridCostModel, NeedsAValidPoint) {
  GridCosts c = compute_grid_costs(scene_arm(), tiny_options());
  for (GridPoint& p : c.points) p.valid = false;
  EXPECT_NE(error_of([&] { GridCostModel m(c); }).find("no trajectory"), std::string::npos);
}

}  // namespace
}  // namespace proprio::planning
