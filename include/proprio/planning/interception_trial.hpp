#pragma once
// The interception experiment of thesis 3.7 in MuJoCo: a target moving at constant velocity is
// seen by the stereo pair at the camera rate, the filter learns its motion, the planner chooses
// a trajectory and an interception time, and the simulated arm follows it with its servos (the
// inverse-dynamics torques fed forward, robot::servo_commands) while the target body moves. The
// miss is the distance between the end-effector and the TRUE target at the interception time.
//
// Optionally (3.8's remedy) the arm re-plans with visual feedback: while it is still at rest,
// every new measurement re-plans from scratch; once it moves, every new measurement re-aims the
// end point at the filter's new prediction for the same time, by a smooth shaped correction
// added to the rest of the path (zero velocity and acceleration where it starts), until
// `replan_cutoff` before the interception.
//
// Times are seconds from the first camera frame; the world frame is the robot base frame.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "proprio/core/random.hpp"
#include "proprio/planning/interception_planner.hpp"
#include "proprio/planning/stereo_rig.hpp"
#include "proprio/planning/target_filter.hpp"
#include "proprio/planning/trajectory_grid.hpp"
#include "proprio/robot/arm.hpp"

namespace proprio::planning {

/// models/intercept.xml in proprio's data directory (core::data_directory()).
std::filesystem::path default_intercept_scene();

/// Where the trajectory costs are cached by default: $XDG_CACHE_HOME/proprio/intercept_grid.json,
/// else ~/.cache/proprio/intercept_grid.json, else the temporary directory.
std::filesystem::path default_grid_cache();

/// A target moving at constant velocity: position(t) = start + velocity t.
struct TargetMotion {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();     ///< m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< m/s
  [[nodiscard]] Eigen::Vector3d position(double t) const { return start + velocity * t; }
};

/// Random targets that cross the interception workspace in the arm's plane.
struct ScenarioOptions {
  double speed_min = 0.05;  ///< m/s
  double speed_max = 0.15;
  /// The target passes its crossing point this long after the earliest possible interception
  /// (first plan + the move's duration), s.
  double crossing_delay_min = 0.2;
  double crossing_delay_max = 1.3;
  /// The crossing point is p0 + l (sin theta, cos theta, 0) with l and |theta| in these ranges
  /// (inside the grid's half-disc).
  double crossing_length_min = 0.09;
  double crossing_length_max = 0.19;
  double crossing_theta_max = 1.2;
  void validate() const;
};

/// A target whose straight path crosses the workspace: a crossing point and direction drawn
/// uniformly, a speed uniformly in the range, at height grid.start.z; `t_plan` is the first
/// plan's time.
TargetMotion random_target(const GridSpec& grid, double t_plan, const ScenarioOptions& options,
                           core::Rng& rng);

struct TrialOptions {
  /// Measurement noise: the per-axis standard deviation of the measured 3D position at the
  /// workspace's reference point, cm. It is produced by Gaussian pixel noise in both cameras (so
  /// it is larger in depth and grows away from the cameras); 0 = exact measurements.
  double noise_cm = 0;
  double camera_rate_hz = 25;
  /// Camera frames measured before the first plan (at least the filter's N + 1).
  int observe_frames = 20;
  bool replan = false;
  /// No re-aiming later than this before the interception, s.
  double replan_cutoff = 0.2;
  FilterOptions filter;    ///< its dt is set from camera_rate_hz
  PlannerOptions planner;  ///< its time_quantum is set to the simulation step
  ScenarioOptions scenario;
  /// Keep the paths and predictions for figures.
  bool record = false;
  void validate() const;
};

/// Throws Error when `options` are out of range or do not fit a scene with simulation step
/// `time_step` and moves of `move_duration` (both s): the camera period and the move must be whole
/// numbers of steps.
void check_trial_options(const TrialOptions& options, double time_step, double move_duration);

/// What a recorded trial saw and did (horizontal plane and heights in the world frame).
struct TrialRecord {
  std::vector<PositionMeasurement> measurements;
  std::vector<TargetEstimate> forecast;    ///< the first plan's predictions up to the interception
  std::vector<Eigen::Vector3d> commanded;  ///< the arm's final commanded path, every frame
  std::vector<Eigen::Vector3d> executed;   ///< the simulated end-effector, every frame
  std::vector<Eigen::Vector3d> aims;       ///< the end point after each (re)plan or re-aim
};

struct TrialResult {
  bool executed = false;  ///< a plan was made and the arm reached the interception time
  std::string why_not;    ///< when !executed
  TargetMotion target;
  double sigma_px = 0;               ///< the pixel noise used
  double miss = 0;                   ///< |ee - true target| at the interception, m
  double plane_miss = 0;             ///< its horizontal part, m
  double predicted_sigma = 0;        ///< the filter's std at the interception when last aimed, m
  double first_predicted_sigma = 0;  ///< and at the first plan, m
  double t_plan = 0;                 ///< first plan, s
  double t_intercept = 0;            ///< s
  double first_plan_ms = 0;          ///< wall time of the first plan
  double total_plan_ms = 0;          ///< all plans and re-aims
  int plans = 0;                     ///< full plans (1 + re-plans before the move)
  int reaims = 0;                    ///< corrections during the move
  int failed_reaims = 0;             ///< corrections whose path could not be tracked (skipped)
  InterceptionPlan first_plan;
  InterceptionPlan final_plan;
  Eigen::Vector3d ee_at = Eigen::Vector3d::Zero();      ///< at the interception
  Eigen::Vector3d target_at = Eigen::Vector3d::Zero();  ///< true, at the interception
  Eigen::Vector3d aim = Eigen::Vector3d::Zero();        ///< the final commanded end point
  std::vector<std::string> mujoco_warnings;
  TrialRecord record;
};

/// Runs trials on a scene that holds the arm and a mocap target body.
class InterceptionSimulator {
 public:
  /// `arm` is read from the scene (e.g. data/models/intercept.xml); `target_body` must be a mocap
  /// body of it. Throws Error when it is missing or not a mocap body, or the scene's time step
  /// is not positive.
  InterceptionSimulator(robot::Arm arm, std::shared_ptr<const GridCostModel> model, StereoRig rig,
                        const std::string& target_body = "target");

  /// Throws Error when the options are out of range or do not fit the scene (the camera period
  /// and the move's duration must be whole numbers of simulation steps).
  void check(const TrialOptions& options) const;

  /// One trial with measurement noise and decisions drawn from `seed`. Bad options are an
  /// Error; a target that cannot be planned for, or a path the arm cannot follow, is a result
  /// with executed = false and the reason.
  [[nodiscard]] TrialResult run(const TargetMotion& target, const TrialOptions& options,
                                std::uint64_t seed) const;

  /// The first plan of run() alone, without simulating the arm: the same measurements (for the
  /// same seed), filter and plan. Throws Error when the filter cannot be built (too few
  /// measurements in the observation window).
  [[nodiscard]] InterceptionPlan first_plan(const TargetMotion& target, const TrialOptions& options,
                                            std::uint64_t seed) const;

  /// The pixel noise std that gives `noise_cm` per axis at reference_point(), px.
  [[nodiscard]] double pixel_noise_for(double noise_cm) const;
  /// The mean of the grid's end points: where noise_cm is calibrated, m.
  [[nodiscard]] Eigen::Vector3d reference_point() const;
  [[nodiscard]] const GridCostModel& model() const { return *model_; }
  [[nodiscard]] const StereoRig& rig() const { return rig_; }
  [[nodiscard]] const robot::Arm& arm() const { return arm_; }
  /// The first plan's time for these options (the last observed frame), s.
  [[nodiscard]] double plan_time(const TrialOptions& options) const;

 private:
  robot::Arm arm_;
  std::shared_ptr<const GridCostModel> model_;
  StereoRig rig_;
  int mocap_ = -1;
};

struct ExperimentOptions {
  TrialOptions trial;
  int trials = 50;
  std::uint64_t seed = 1;
  void validate() const;
};

/// Figures over the executed trials (NaN-free: zero when none was executed).
struct ExperimentSummary {
  int trials = 0;
  int executed = 0;
  int not_planned = 0;                    ///< no feasible plan (e.g. the target out of reach)
  int not_executed = 0;                   ///< all trials not executed, with not_planned among them
  double mean_miss = 0;                   ///< m
  double median_miss = 0;                 ///< m
  double max_miss = 0;                    ///< m
  double mean_plane_miss = 0;             ///< m
  double mean_predicted_sigma = 0;        ///< m, at the last aim
  double mean_first_predicted_sigma = 0;  ///< m, at the first plan
  double mean_intercept_time = 0;         ///< interception minus first plan, s
  double mean_plan_ms = 0;                ///< first plans
  double max_plan_ms = 0;
  double mean_reaims = 0;
  int mujoco_warnings = 0;  ///< trials with a MuJoCo warning
  double sigma_px = 0;      ///< pixel noise of the trials
};

struct ExperimentResult {
  ExperimentOptions options;
  std::vector<TrialResult> trials;
  ExperimentSummary summary;
};

/// Runs `trials` trials, trial k with a target from random_target and noise from its own
/// stream of `seed`, so results repeat exactly for a seed.
ExperimentResult run_experiment(const InterceptionSimulator& simulator,
                                const ExperimentOptions& options, bool show_progress = false);

/// The summary of a set of trials.
ExperimentSummary summarise(const std::vector<TrialResult>& trials);

}  // namespace proprio::planning
