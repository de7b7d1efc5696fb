#pragma once
// `proprio intercept` and `proprio intercept sweep` as library calls: the interception scene set
// up once (arm, stereo rig, trajectory costs), then a set of trials (thesis 3.3-3.8) or the sweep
// behind Figs 3-8, 3-10 and 3-11 with its JSON table (docs/results/interception.md).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/planning/interception_planner.hpp"
#include "proprio/planning/interception_trial.hpp"
#include "proprio/planning/target_filter.hpp"

namespace proprio::planning {

/// What the experiment and the sweep share: the scene, the cameras and the trajectory costs.
struct InterceptionSetupOptions {
  /// MJCF scene with the arm and a mocap body "target"; empty = default_intercept_scene().
  std::filesystem::path scene;
  /// Trajectory cost cache; empty = default_grid_cache(). Recomputed when the arm model or the
  /// grid changes.
  std::filesystem::path cache;
  /// calib.yml of the left and right cameras: both or neither (neither = default_stereo_rig()).
  std::filesystem::path calib_left, calib_right;
  TransitionModel transition = TransitionModel::kLearned;  ///< the target model (3.5)
  int precision_samples = 500;  ///< perturbed end points per trajectory (eq 3.42), >= 2
  int threads = 0;              ///< for the trajectory costs (0 = all cores)
  double camera_rate_hz = 25;   ///< camera frame rate, > 0
  int observe_frames = 20;      ///< frames measured before the first plan, >= 4
  double window = 1.5;          ///< interception times considered after the move, s, [0, 60]
  bool progress = false;        ///< progress bars on stderr

  /// Throws Error naming the first bad option.
  void validate() const;
};

/// The trajectory grid's costs as the result documents list them ("grid").
struct GridRecord {
  std::filesystem::path scene, cache;
  std::string key;     ///< grid_cache_key of the arm and options
  std::string source;  ///< "computed", "cache", or "computed (cache ...)"
  std::size_t trajectories = 0;
  int valid = 0;
  int precision_samples = 0;
  double compute_seconds = 0;  ///< 0 when read from the cache

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.scene, {"scene", "The arm's MJCF scene"});
    v(self.cache, {"cache", "The costs' cache file"});
    v(self.key, {"key", "The cache key of the arm and grid options"});
    v(self.source, {"source", "computed or cache"});
    v(self.trajectories, {"trajectories", "Trajectories of the grid"});
    v(self.valid, {"valid", "Of them valid"});
    v(self.precision_samples, {"precision_samples", "Samples of each trajectory's precision"});
    v(self.compute_seconds, {"compute_seconds", "Time to compute the costs, s (0: cache)"});
  }
};

/// An ExperimentSummary's fields as a record lists them (lengths in mm), flat.
template <class Visitor>
void describe_experiment_summary(const ExperimentSummary& s, Visitor& v) {
  constexpr double kMm = 1e3;
  v(s.trials, {"trials", "Trials"});
  v(s.executed, {"executed", "Trials executed"});
  v(s.not_executed, {"not_executed", "Trials not executed (not_planned among them)"});
  v(s.not_planned, {"not_planned", "No feasible plan"});
  v(s.sigma_px, {"sigma_px", "Pixel noise of the trials"});
  v(s.mean_miss * kMm, {"mean_miss_mm", "Mean miss, mm"});
  v(s.median_miss * kMm, {"median_miss_mm", "Median miss, mm"});
  v(s.max_miss * kMm, {"max_miss_mm", "Largest miss, mm"});
  v(s.mean_plane_miss * kMm, {"mean_plane_miss_mm", "Mean miss in the plane, mm"});
  v(s.mean_predicted_sigma * kMm,
    {"mean_predicted_sigma_mm", "Mean predicted std at the last aim, mm"});
  v(s.mean_first_predicted_sigma * kMm,
    {"mean_first_predicted_sigma_mm", "Mean predicted std at the first plan, mm"});
  v(s.mean_predicted_sigma > 0 ? s.mean_miss / s.mean_predicted_sigma : 0.0,
    {"miss_over_predicted_sigma", "Mean miss over mean predicted std (0: none)"});
  v(s.mean_intercept_time, {"mean_intercept_time_s", "Interception minus first plan, mean, s"});
  v(s.mean_plan_ms, {"mean_plan_ms", "First plans, mean, ms"});
  v(s.max_plan_ms, {"max_plan_ms", "First plans, most, ms"});
  v(s.mean_reaims, {"mean_reaims", "Corrections during the move, mean"});
  v(s.mujoco_warnings, {"mujoco_warning_trials", "Trials with a MuJoCo warning"});
}

/// One trial as the result record lists it (the last four only when it was executed).
struct TrialRow {
  bool executed = false;
  std::string why_not;
  double plan_ms = 0;
  int plans = 0;
  int reaims = 0;
  std::optional<double> miss_mm;
  std::optional<double> predicted_sigma_mm;
  std::optional<double> intercept_time_s;
  std::optional<std::vector<double>> psi;

  /// The record of `t`.
  [[nodiscard]] static TrialRow of(const TrialResult& t);

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.executed, {"executed", "A plan was made and the arm reached the interception time"});
    v(self.why_not, {"why_not", "Why not, when not executed"});
    v(self.plan_ms, {"plan_ms", "Wall time of the first plan, ms"});
    v(self.plans, {"plans", "Full plans"});
    v(self.reaims, {"reaims", "Corrections during the move"});
    v(self.miss_mm, {"miss_mm", "Miss at the interception, mm"});
    v(self.predicted_sigma_mm, {"predicted_sigma_mm", "The filter's std when last aimed, mm"});
    v(self.intercept_time_s, {"intercept_time_s", "Interception time after the plan, s"});
    v(self.psi, {"psi", "The final plan's theta, length, gamma"});
  }
};

/// A row of the sweep: one target model, noise level and re-planning switch, and its summary.
struct SweepRow {
  std::string transition;
  double noise_cm = 0;
  bool replan = false;
  ExperimentSummary summary;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.transition, {"transition", "The filter's target model"});
    v(self.noise_cm, {"noise_cm", "Observation noise, cm"});
    v(self.replan, {"replan", "Whether the trials re-planned"});
    describe_experiment_summary(self.summary, v);
  }
};

/// A point of Fig 3-11: the first plan's interception time over noise draws.
struct NoiseChoiceRecord {
  std::string transition;
  std::string prior;
  double noise_cm = 0;
  int draws = 0;                     ///< draws with a feasible plan
  double mean_intercept_time_s = 0;  ///< interception minus first plan, s
  double std_intercept_time_s = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.transition, {"transition", "The filter's target model"});
    v(self.prior, {"prior", "The planner's prior mode"});
    v(self.noise_cm, {"noise_cm", "Observation noise, cm"});
    v(self.draws, {"draws", "Draws with a feasible plan"});
    v(self.mean_intercept_time_s, {"mean_intercept_time_s", "Interception after the plan, s"});
    v(self.std_intercept_time_s, {"std_intercept_time_s", "Its std over the draws, s"});
  }
};

/// The scene ready for trials. Constant once made.
struct InterceptionSetup {
  std::filesystem::path scene, cache;
  std::unique_ptr<InterceptionSimulator> simulator;
  std::shared_ptr<const GridCostModel> model;
  TrialOptions trial;  ///< the setup's trial options (camera, filter, window)

  /// The "grid" of the result documents.
  [[nodiscard]] GridRecord grid_record() const;
  /// "trajectory costs: V of N trajectories valid (SOURCE, CACHE)".
  [[nodiscard]] std::string brief() const;
};

/// Checks everything that can be checked before the (possibly long) trajectory costs, then
/// loads the scene and computes or loads the costs. `trial` carries the caller's noise, prior and
/// re-planning; the setup's options fill in the rest.
InterceptionSetup make_interception_setup(const InterceptionSetupOptions& options,
                                          TrialOptions trial = {});

struct InterceptionRunOptions {
  InterceptionSetupOptions setup;
  double noise_cm = 0;  ///< per-axis measurement std at the workspace centre, cm, [0, 100]
  int trials = 50;      ///< >= 1
  PriorMode prior = PriorMode::kBoth;
  bool replan = false;     ///< re-plan with visual feedback (3.8)
  std::uint64_t seed = 1;  ///< of the targets and the noise

  void validate() const;
};

// The implicit noexcept move of core::Json (nlohmann's) calls its assert_invariant(), which
// clang-tidy 14 cannot prove free of exceptions.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct InterceptionRunResult {
  std::string setup_brief;  ///< InterceptionSetup::brief()
  ExperimentResult experiment;
  double noise_cm = 0;                  ///< the options' noise, cm
  std::string prior;                    ///< the planner's prior mode
  bool replan = false;                  ///< whether the trials re-planned
  std::string transition;               ///< the filter's target model
  double camera_rate_hz = 0;            ///< Hz
  int observe_frames = 0;               ///< frames observed before the first plan
  GridRecord grid;                      ///< InterceptionSetup::grid_record()
  std::vector<TrialRow> trial_results;  ///< one per trial
  /// Format "proprio.intercept": the fields described below.
  core::Json document;

  std::string message;  ///< one line: what happened (brief()'s first line)
  /// The setup line, the summary line and one line per trial not executed.
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.noise_cm, {"noise_cm", "Observation noise, cm"});
    v(self.prior, {"prior", "The planner's prior mode"});
    v(self.replan, {"replan", "Whether the trials re-planned"});
    v(self.transition, {"transition", "The filter's target model"});
    v(self.camera_rate_hz, {"camera_rate_hz", "Camera rate, Hz"});
    v(self.observe_frames, {"observe_frames", "Frames observed before the first plan"});
    v(self.grid, {"grid", "The trajectory grid"});
    describe_experiment_summary(self.experiment.summary, v);
    v(self.trial_results, {"trial_results", "One object per trial"});
  }
};

/// Sets up the scene and runs the trials.
InterceptionRunResult run_interception(const InterceptionRunOptions& options,
                                       const core::Provenance& provenance);

struct InterceptionSweepOptions {
  InterceptionSetupOptions setup;
  std::filesystem::path out;  ///< directory to write (required)
  bool overwrite = false;     ///< replace `out` when it exists
  int trials = 50;            ///< per noise level and re-planning switch
  std::uint64_t seed = 1;
  std::vector<double> noise = {0, 0.25, 0.5, 1, 1.5, 2, 2.5, 3};  ///< cm, each in [0, 100]
  std::vector<TransitionModel> transitions = {TransitionModel::kLearned,
                                              TransitionModel::kConstantVelocity};
  std::vector<double> choice_noise = {0, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 3};  ///< Fig 3-11, cm
  int choice_draws = 10;      ///< noise draws per point of Fig 3-11, >= 1
  double figure_noise = 1.5;  ///< noise of the Fig 3-10 trial, cm

  void validate() const;
};

// The implicit noexcept move of core::Json (nlohmann's) calls its assert_invariant(), which
// clang-tidy 14 cannot prove free of exceptions.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct InterceptionSweepResult {
  std::string setup_brief;
  std::vector<std::string> files;  ///< sweep.json and the PNGs, in `out`
  /// sweep.json (format "proprio.intercept.sweep"): the fields described below.
  core::Json document;
  std::filesystem::path out;
  int trials = 0;                                       ///< trials per row
  std::vector<double> noise_cm;                         ///< the noise levels, cm
  GridRecord grid;                                      ///< InterceptionSetup::grid_record()
  std::vector<SweepRow> rows;                           ///< per target model, noise and re-planning
  std::vector<NoiseChoiceRecord> interception_choices;  ///< the Fig 3-11 choices

  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.trials, {"trials", "Trials per row"});
    v(self.noise_cm, {"noise_cm", "The noise levels, cm"});
    v(std::string("both"), {"prior", "The prior modes compared"});
    v(self.grid, {"grid", "The trajectory grid"});
    v(self.rows, {"rows", "Per target model, noise and re-planning: the summary"});
    v(self.interception_choices, {"interception_choices", "The Fig 3-11 choices"});
  }
};

/// The sweep: for each target model, every noise level open loop and re-planning; the Fig 3-10
/// trial and the Fig 3-11 choices; the energy grid (Fig 3-8). Writes `out` atomically.
InterceptionSweepResult run_interception_sweep(const InterceptionSweepOptions& options,
                                               const core::Provenance& provenance);

}  // namespace proprio::planning
