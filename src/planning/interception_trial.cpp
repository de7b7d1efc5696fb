#include "proprio/planning/interception_trial.hpp"
#include "proprio/core/random.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <optional>

#include "proprio/core/data_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/robot/dynamics.hpp"
#include "proprio/robot/mujoco_ptr.hpp"
#include "text.hpp"

namespace proprio::planning {

using detail::cat;
using detail::num;

std::filesystem::path default_intercept_scene() {
  return core::data_directory() / "models" / "intercept.xml";
}

std::filesystem::path default_grid_cache() {
  namespace fs = std::filesystem;
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg != nullptr && xdg[0] != '\0') return fs::path(xdg) / "proprio" / "intercept_grid.json";
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] != '\0') {
    return fs::path(home) / ".cache" / "proprio" / "intercept_grid.json";
  }
  return fs::temp_directory_path() / "proprio_intercept_grid.json";
}

void ScenarioOptions::validate() const {
  require(std::isfinite(speed_min) && std::isfinite(speed_max) && speed_min > 0 &&
              speed_min <= speed_max,
          "ScenarioOptions: speeds must satisfy 0 < speed_min <= speed_max");
  require(std::isfinite(crossing_delay_min) && std::isfinite(crossing_delay_max) &&
              crossing_delay_min >= 0 && crossing_delay_min <= crossing_delay_max,
          "ScenarioOptions: crossing delays must satisfy 0 <= min <= max");
  require(std::isfinite(crossing_length_min) && std::isfinite(crossing_length_max) &&
              crossing_length_min > 0 && crossing_length_min <= crossing_length_max,
          "ScenarioOptions: crossing lengths must satisfy 0 < min <= max");
  require(std::isfinite(crossing_theta_max) && crossing_theta_max >= 0 &&
              crossing_theta_max <= std::numbers::pi,
          "ScenarioOptions: crossing_theta_max must be in [0, pi]");
}

TargetMotion random_target(const GridSpec& grid, double t_plan, const ScenarioOptions& o,
                           core::Rng& rng) {
  o.validate();
  const double l = rng.uniform(o.crossing_length_min, o.crossing_length_max);
  const double theta = rng.uniform(-o.crossing_theta_max, o.crossing_theta_max);
  const Eigen::Vector3d crossing =
      grid.start + l * Eigen::Vector3d(std::sin(theta), std::cos(theta), 0);
  const double heading = rng.uniform(-std::numbers::pi, std::numbers::pi);
  const double speed = rng.uniform(o.speed_min, o.speed_max);
  const double t_cross =
      t_plan + grid.duration + rng.uniform(o.crossing_delay_min, o.crossing_delay_max);
  TargetMotion m;
  m.velocity = speed * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
  m.start = crossing - m.velocity * t_cross;
  return m;
}

void TrialOptions::validate() const {
  require(std::isfinite(noise_cm) && noise_cm >= 0 && noise_cm <= 100,
          "noise must be in [0, 100] cm");
  require(std::isfinite(camera_rate_hz) && camera_rate_hz > 0 && camera_rate_hz <= 1000,
          "camera rate must be in (0, 1000] Hz");
  require(observe_frames >= filter.learn_states + 1 && observe_frames <= 100000,
          cat({"observe_frames must be at least the filter's N + 1 = ",
               std::to_string(filter.learn_states + 1)}));
  require(std::isfinite(replan_cutoff) && replan_cutoff >= 0, "replan_cutoff must be >= 0 s");
  filter.validate();
  planner.validate();
  scenario.validate();
}

void ExperimentOptions::validate() const {
  trial.validate();
  require(trials >= 1 && trials <= 1000000, "trials must be in [1, 1000000]");
}

namespace {

// The arm's commanded Cartesian path: a psi trajectory that starts at t_start, plus shaped
// corrections (re-aiming) that each start at rest at their own time. Times are since t_start.
class CommandedPath final : public robot::CartesianTrajectory {
 public:
  CommandedPath(robot::BezierTrajectory base, double t_start)
      : base_(std::move(base)), t_start_(t_start), end_(base_.p2()) {}

  [[nodiscard]] double duration() const override { return base_.duration(); }
  [[nodiscard]] double t_start() const { return t_start_; }
  [[nodiscard]] const Eigen::Vector3d& end() const { return end_; }

  [[nodiscard]] robot::CartesianSample sample(double t) const override {
    robot::CartesianSample s = base_.sample(t);
    for (const Correction& c : corrections_) {
      const double tau = t - c.begin;
      if (tau <= 0) continue;
      const robot::Shaped f = c.shaping(std::min(tau, c.shaping.duration()));
      s.position += f.value * c.delta;
      s.velocity += f.rate * c.delta;
      s.acceleration += f.accel * c.delta;
    }
    return s;
  }

  /// Adds `delta` (m) smoothly between `begin` and the end of the path (times since t_start).
  void add_correction(double begin, const Eigen::Vector3d& delta) {
    corrections_.push_back({begin, robot::TimeShaping(duration() - begin), delta});
    end_ += delta;
  }

 private:
  struct Correction {
    double begin;
    robot::TimeShaping shaping;
    Eigen::Vector3d delta;
  };
  robot::BezierTrajectory base_;
  double t_start_;
  Eigen::Vector3d end_;
  std::vector<Correction> corrections_;
};

// The part [from, to] of a trajectory, re-timed to start at 0.
class Window final : public robot::CartesianTrajectory {
 public:
  Window(const robot::CartesianTrajectory& inner, double from, double to)
      : inner_(inner), from_(from), to_(to) {}
  [[nodiscard]] double duration() const override { return to_ - from_; }
  [[nodiscard]] robot::CartesianSample sample(double t) const override {
    robot::CartesianSample s = inner_.sample(from_ + std::clamp(t, 0.0, duration()));
    s.t = t;
    return s;
  }

 private:
  const robot::CartesianTrajectory& inner_;
  double from_, to_;
};

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// One trial of InterceptionSimulator::run: the arm waits at rest while the cameras observe the
// target, plans at the end of the observation (then again while it waits, and re-aims while it
// moves, with options.replan), and the trial ends when the planned interception time comes.
class TrialRun {
 public:
  TrialRun(const robot::Arm& arm, const GridCostModel& model, const StereoRig& rig, int mocap,
           const TrialOptions& options, std::uint64_t seed, TrialResult r)
      : arm_(arm),
        m_(arm.model()),
        model_(model),
        rig_(rig),
        mocap_(mocap),
        options_(options),
        h_(m_.opt.timestep),
        spf_(std::lround(1 / (options.camera_rate_hz * h_))),
        grid_(model.grid()),
        motion_(model.costs().options.motion),
        fo_(filter_options(options.filter, static_cast<double>(spf_) * h_)),
        po_(planner_options(options.planner, h_)),
        rate_(1 / h_),
        r_(std::move(r)),
        rng_(seed),
        state_(arm) {}

  TrialResult run();

 private:
  static FilterOptions filter_options(FilterOptions fo, double dt) {
    fo.dt = dt;
    return fo;
  }
  static PlannerOptions planner_options(PlannerOptions po, double time_quantum) {
    po.time_quantum = time_quantum;
    return po;
  }

  void start_at_rest();
  bool on_frame(long i, double t, const Eigen::Vector3d& truth);
  void record_frame(long i, double t, const std::optional<PositionMeasurement>& pm);
  bool plan_first(long i, double t);
  void replan(long i, double t);
  std::pair<InterceptionPlan, double> plan_now(double t, double t_latest);
  void schedule(const InterceptionPlan& plan, long now);
  void reaim(long now);
  void step(long i);
  void finish_at_hit();
  [[nodiscard]] Eigen::Vector3d ee_position() const {
    const int ee = arm_.ee_site();
    return {d_->site_xpos[3 * ee], d_->site_xpos[3 * ee + 1], d_->site_xpos[3 * ee + 2]};
  }

  const robot::Arm& arm_;
  const mjModel& m_;
  const GridCostModel& model_;
  const StereoRig& rig_;
  int mocap_;
  const TrialOptions& options_;
  double h_;  // simulation step, s
  long spf_;  // simulation steps per camera frame
  const GridSpec& grid_;
  const ArmMotionOptions& motion_;
  FilterOptions fo_;
  PlannerOptions po_;
  double rate_;  // simulation steps per second
  TrialResult r_;
  core::Rng rng_;
  robot::ArmState state_;
  robot::JointVector q0_;    // the arm at rest at the grid's start
  robot::JointVector hold_;  // the commands that hold it there
  robot::DataPtr d_;
  std::vector<robot::JointVector> ctrl_, qcmd_;  // per simulation step, once a move is planned
  std::optional<CommandedPath> path_;
  long s_start_ = -1, s_hit_ = -1;  // the move's first step and the interception's
  std::optional<TargetFilter> filter_;
  std::vector<PositionMeasurement> observed_;  // before the filter is built
};

TrialResult TrialRun::run() {
  start_at_rest();
  const long last_step =
      std::lround((r_.t_plan + grid_.duration + 2 * po_.window + 2 * fo_.dt) / h_);
  for (long i = 0; i <= last_step; ++i) {
    const double t = static_cast<double>(i) * h_;
    const Eigen::Vector3d truth = r_.target.position(t);
    for (int k = 0; k < 3; ++k) d_->mocap_pos[3 * mocap_ + k] = truth[k];
    if (i % spf_ == 0 && !on_frame(i, t, truth)) return std::move(r_);
    step(i);
    if (s_hit_ >= 0 && i + 1 == s_hit_) {
      finish_at_hit();
      return std::move(r_);
    }
  }
  r_.why_not = "the interception time was never reached";
  return std::move(r_);
}

// The arm at rest at the grid's start, held there by constant commands; the target at its start.
void TrialRun::start_at_rest() {
  q0_ = solve_scheduled(state_, grid_.start, arm_.clamp(robot::JointVector::Zero()), motion_).q;
  robot::JointTrajectory rest;
  rest.dt = h_;
  rest.q = {q0_};
  rest.qdot = rest.qddot = {robot::JointVector::Zero()};
  hold_ = robot::servo_commands(arm_, rest, robot::inverse_dynamics(state_, rest)).front();
  d_ = robot::make_data(m_);
  for (int k = 0; k < robot::kArmJoints; ++k) d_->qpos[arm_.qpos_adr(k)] = q0_[k];
  for (int k = 0; k < 3; ++k) d_->mocap_pos[3 * mocap_ + k] = r_.target.start[k];
  mj_forward(&m_, d_.get());
}

// A camera frame at step `i`: the target is measured, then either observed (the filter is built
// and the first plan made at the last observed frame) or tracked (the filter updated, and with
// options.replan a new plan or a re-aim). Returns false when the trial ends here.
bool TrialRun::on_frame(long i, double t, const Eigen::Vector3d& truth) {
  std::optional<PositionMeasurement> pm;
  if (const auto sm = measure(rig_, truth, r_.sigma_px, rng_)) {
    pm = PositionMeasurement{t, sm->position, sm->covariance};
  }
  if (options_.record) record_frame(i, t, pm);
  if (!filter_) {
    if (pm) observed_.push_back(*pm);
    if (i / spf_ == options_.observe_frames - 1) return plan_first(i, t);
  } else if (pm) {
    filter_->update(*pm);
    if (options_.replan) replan(i, t);
  }
  return true;
}

void TrialRun::record_frame(long i, double t, const std::optional<PositionMeasurement>& pm) {
  if (pm) r_.record.measurements.push_back(*pm);
  mj_kinematics(&m_, d_.get());
  r_.record.executed.push_back(ee_position());
  r_.record.commanded.push_back(
      path_ && i >= s_start_ ? path_->sample(t - path_->t_start()).position : grid_.start);
}

// Builds the filter from the observed frames and commits the first plan. Returns false, with
// the reason, when there is no filter, no feasible plan or no path the arm can follow.
bool TrialRun::plan_first(long i, double t) {
  try {
    filter_.emplace(observed_, fo_);
  } catch (const Error& e) {
    r_.why_not = e.what();
    return false;
  }
  const auto [plan, ms] = plan_now(t, std::numeric_limits<double>::infinity());
  r_.first_plan = plan;
  r_.first_plan_ms = ms;
  r_.first_predicted_sigma = plan.predicted_sigma;
  if (!plan.feasible) {
    r_.final_plan = plan;
    r_.why_not = plan.why_not;
    return false;
  }
  try {
    schedule(plan, i);
  } catch (const Error& e) {
    r_.why_not = cat({"the arm cannot follow the planned path: ", e.what()});
    return false;
  }
  if (options_.record) r_.record.forecast = TargetForecast(*filter_, plan.t_intercept).frames();
  return true;
}

// Visual feedback: while the arm waits, a new plan; once it moves, a re-aim (until the cutoff).
void TrialRun::replan(long i, double t) {
  if (i < s_start_) {
    // Waiting at rest: plan again, no later than the committed interception (so that re-plans
    // cannot put the move off for ever).
    const auto [plan, ms] = plan_now(t, static_cast<double>(s_hit_) * h_);
    if (plan.feasible) {
      try {
        schedule(plan, i);
      } catch (const Error&) {
        // keep the current plan
      }
    }
  } else if (static_cast<double>(s_hit_ - i) * h_ >= options_.replan_cutoff - 1e-9) {
    reaim(i);
  }
}

std::pair<InterceptionPlan, double> TrialRun::plan_now(double t, double t_latest) {
  const auto clock0 = std::chrono::steady_clock::now();
  InterceptionPlan plan = plan_interception(*filter_, model_, t, po_, t_latest);
  const double ms = ms_since(clock0);
  r_.total_plan_ms += ms;
  ++r_.plans;
  return std::pair{plan, ms};
}

// Commits a plan made at step `now` (the arm at rest): joint path, feed-forward commands.
void TrialRun::schedule(const InterceptionPlan& plan, long now) {
  const long b = std::lround(plan.t_intercept / h_);
  const long a = b - std::lround(grid_.duration / h_);
  ensure(a >= now && b > a, "a plan must start after it is made");
  CommandedPath p(grid_.trajectory(plan.psi), static_cast<double>(a) * h_);
  const robot::TrackResult track = track_scheduled(state_, p, q0_, rate_, motion_);
  ensure(static_cast<long>(track.joints.size()) == b - a + 1,
         "the joint path does not match the simulation steps");
  const auto cmd =
      robot::servo_commands(arm_, track.joints, robot::inverse_dynamics(state_, track.joints));
  ctrl_.assign(static_cast<std::size_t>(b) + 1, hold_);
  qcmd_.assign(static_cast<std::size_t>(b) + 1, q0_);
  for (long k = 0; k <= b - a; ++k) {
    ctrl_[static_cast<std::size_t>(a + k)] = cmd[static_cast<std::size_t>(k)];
    qcmd_[static_cast<std::size_t>(a + k)] = track.joints.q[static_cast<std::size_t>(k)];
  }
  path_.emplace(std::move(p));
  s_start_ = a;
  s_hit_ = b;
  r_.aim = plan.end_point;
  r_.final_plan = plan;
  r_.predicted_sigma = plan.predicted_sigma;
  r_.t_intercept = plan.t_intercept;
  if (options_.record) r_.record.aims.push_back(plan.end_point);
}

// Re-aims the moving arm at the filter's prediction for the interception time.
void TrialRun::reaim(long now) {
  const double t_hit = static_cast<double>(s_hit_) * h_;
  const auto clock0 = std::chrono::steady_clock::now();
  const TargetForecast forecast(*filter_, t_hit);
  Eigen::Vector3d mean;
  Eigen::Matrix3d cov;
  forecast.at(t_hit, &mean, &cov);
  const Eigen::Vector3d delta(mean.x() - path_->end().x(), mean.y() - path_->end().y(), 0);
  if (!delta.allFinite() || !cov.allFinite()) {
    ++r_.failed_reaims;
    return;
  }
  CommandedPath next = *path_;
  const double from = static_cast<double>(now - s_start_) * h_;
  next.add_correction(from, delta);
  try {
    const Window rest_of_path(next, from, static_cast<double>(s_hit_ - s_start_) * h_);
    const robot::TrackResult track =
        track_scheduled(state_, rest_of_path, qcmd_[static_cast<std::size_t>(now)], rate_, motion_);
    ensure(static_cast<long>(track.joints.size()) == s_hit_ - now + 1,
           "the corrected joint path does not match the simulation steps");
    const auto cmd =
        robot::servo_commands(arm_, track.joints, robot::inverse_dynamics(state_, track.joints));
    for (long k = 0; k <= s_hit_ - now; ++k) {
      ctrl_[static_cast<std::size_t>(now + k)] = cmd[static_cast<std::size_t>(k)];
      qcmd_[static_cast<std::size_t>(now + k)] = track.joints.q[static_cast<std::size_t>(k)];
    }
  } catch (const Error&) {
    ++r_.failed_reaims;  // the corrected path leaves the workspace: keep the current one
    r_.total_plan_ms += ms_since(clock0);
    return;
  }
  *path_ = std::move(next);
  r_.aim = path_->end();
  r_.predicted_sigma = std::sqrt(cov.topLeftCorner<2, 2>().trace() / 2);
  ++r_.reaims;
  r_.total_plan_ms += ms_since(clock0);
  if (options_.record) r_.record.aims.push_back(r_.aim);
}

// One simulation step under the commands for step `i` (the hold before a move is planned, the
// last command after the move's end).
void TrialRun::step(long i) {
  const robot::JointVector& u =
      ctrl_.empty()
          ? hold_
          : ctrl_[static_cast<std::size_t>(std::min<long>(i, static_cast<long>(ctrl_.size()) - 1))];
  for (int k = 0; k < robot::kArmJoints; ++k) d_->ctrl[arm_.actuator_id(k)] = u[k];
  mj_step(&m_, d_.get());
}

// The interception time has come: where the hand and the target are, and the miss.
void TrialRun::finish_at_hit() {
  mj_kinematics(&m_, d_.get());
  r_.ee_at = ee_position();
  r_.target_at = r_.target.position(static_cast<double>(s_hit_) * h_);
  r_.miss = (r_.ee_at - r_.target_at).norm();
  r_.plane_miss = (r_.ee_at - r_.target_at).head<2>().norm();
  r_.executed = true;
  r_.mujoco_warnings = robot::warnings(*d_);
  if (options_.record) {
    r_.record.executed.push_back(r_.ee_at);
    r_.record.commanded.push_back(path_->end());
  }
}

}  // namespace

InterceptionSimulator::InterceptionSimulator(robot::Arm arm,
                                             std::shared_ptr<const GridCostModel> model,
                                             StereoRig rig, const std::string& target_body)
    : arm_(std::move(arm)), model_(std::move(model)), rig_(std::move(rig)) {
  assert(model_ != nullptr);
  const mjModel& m = arm_.model();
  const int body = mj_name2id(&m, mjOBJ_BODY, target_body.c_str());
  if (body < 0) {
    throw Error(cat({arm_.source(), ": the scene has no target body '", target_body, "'"}));
  }
  mocap_ = m.body_mocapid[body];
  if (mocap_ < 0) {
    throw Error(
        cat({arm_.source(), ": body '", target_body, "' is not a mocap body (mocap=\"true\")"}));
  }
  require(m.opt.timestep > 0, "the scene's time step must be > 0");
}

Eigen::Vector3d InterceptionSimulator::reference_point() const {
  const GridSpec& g = model_->grid();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < g.size(); ++i) sum += g.end_point(g.params(i));
  return sum / g.size();
}

double InterceptionSimulator::pixel_noise_for(double noise_cm) const {
  require(std::isfinite(noise_cm) && noise_cm >= 0, "noise must be >= 0 cm");
  return noise_cm / 100 / position_std_per_pixel(rig_, reference_point());
}

double InterceptionSimulator::plan_time(const TrialOptions& options) const {
  const double h = arm_.model().opt.timestep;
  const long spf = std::lround(1 / (options.camera_rate_hz * h));
  return static_cast<double>(options.observe_frames - 1) * static_cast<double>(spf) * h;
}

void InterceptionSimulator::check(const TrialOptions& options) const {
  check_trial_options(options, arm_.model().opt.timestep, model_->grid().duration);
}

void check_trial_options(const TrialOptions& options, double h, double move_duration) {
  options.validate();
  require(std::isfinite(h) && h > 0, "the simulation step must be > 0 s");
  const double steps_per_frame = 1 / (options.camera_rate_hz * h);
  const long spf = std::lround(steps_per_frame);
  if (spf < 1 || std::abs(steps_per_frame - static_cast<double>(spf)) > 1e-6) {
    throw Error(cat({"the camera period 1/", num(options.camera_rate_hz),
                     " s must be a whole number of simulation steps of ", num(h), " s"}));
  }
  const double steps_per_move = move_duration / h;
  if (std::abs(steps_per_move - std::round(steps_per_move)) > 1e-6) {
    throw Error(cat({"the move's duration ", num(move_duration),
                     " s must be a whole number of simulation steps of ", num(h), " s"}));
  }
}

TrialResult InterceptionSimulator::run(const TargetMotion& target, const TrialOptions& options,
                                       std::uint64_t seed) const {
  check(options);
  require(target.start.allFinite() && target.velocity.allFinite(),
          "the target's motion must be finite");
  TrialResult r;
  r.target = target;
  r.sigma_px = pixel_noise_for(options.noise_cm);
  r.t_plan = plan_time(options);
  return TrialRun(arm_, *model_, rig_, mocap_, options, seed, std::move(r)).run();
}

InterceptionPlan InterceptionSimulator::first_plan(const TargetMotion& target,
                                                   const TrialOptions& options,
                                                   std::uint64_t seed) const {
  check(options);
  const double h = arm_.model().opt.timestep;
  const long spf = std::lround(1 / (options.camera_rate_hz * h));
  FilterOptions fo = options.filter;
  fo.dt = static_cast<double>(spf) * h;
  PlannerOptions po = options.planner;
  po.time_quantum = h;
  const double sigma_px = pixel_noise_for(options.noise_cm);
  core::Rng rng(seed);
  std::vector<PositionMeasurement> observed;
  for (long f = 0; f < options.observe_frames; ++f) {
    const double t = static_cast<double>(f * spf) * h;
    if (const auto sm = measure(rig_, target.position(t), sigma_px, rng)) {
      observed.push_back({t, sm->position, sm->covariance});
    }
  }
  const TargetFilter filter(observed, fo);
  return plan_interception(filter, *model_, plan_time(options), po);
}

ExperimentSummary summarise(const std::vector<TrialResult>& trials) {
  ExperimentSummary s;
  s.trials = static_cast<int>(trials.size());
  std::vector<double> misses;
  for (const TrialResult& t : trials) {
    s.sigma_px = t.sigma_px;
    if (!t.executed) {
      ++s.not_executed;
      if (!t.first_plan.feasible || !t.final_plan.feasible) ++s.not_planned;
      continue;
    }
    ++s.executed;
    misses.push_back(t.miss);
    s.mean_miss += t.miss;
    s.max_miss = std::max(s.max_miss, t.miss);
    s.mean_plane_miss += t.plane_miss;
    s.mean_predicted_sigma += t.predicted_sigma;
    s.mean_first_predicted_sigma += t.first_predicted_sigma;
    s.mean_intercept_time += t.t_intercept - t.t_plan;
    s.mean_plan_ms += t.first_plan_ms;
    s.max_plan_ms = std::max(s.max_plan_ms, t.first_plan_ms);
    s.mean_reaims += t.reaims;
    if (!t.mujoco_warnings.empty()) ++s.mujoco_warnings;
  }
  if (s.executed > 0) {
    const double n = s.executed;
    s.mean_miss /= n;
    s.mean_plane_miss /= n;
    s.mean_predicted_sigma /= n;
    s.mean_first_predicted_sigma /= n;
    s.mean_intercept_time /= n;
    s.mean_plan_ms /= n;
    s.mean_reaims /= n;
    std::sort(misses.begin(), misses.end());
    const std::size_t k = misses.size() / 2;
    s.median_miss = misses.size() % 2 ? misses[k] : 0.5 * (misses[k - 1] + misses[k]);
  }
  return s;
}

ExperimentResult run_experiment(const InterceptionSimulator& simulator,
                                const ExperimentOptions& options, bool show_progress) {
  options.validate();
  simulator.check(options.trial);
  ExperimentResult result;
  result.options = options;
  const double t_plan = simulator.plan_time(options.trial);
  core::ProgressBar bar(static_cast<std::size_t>(options.trials), "interception trials",
                        show_progress);
  for (int k = 0; k < options.trials; ++k) {
    auto rng = core::Rng::stream(options.seed, static_cast<std::uint64_t>(k));
    const TargetMotion target =
        random_target(simulator.model().grid(), t_plan, options.trial.scenario, rng);
    result.trials.push_back(simulator.run(target, options.trial, rng.next_seed()));
    bar.tick();
  }
  bar.finish();
  result.summary = summarise(result.trials);
  return result;
}

}  // namespace proprio::planning
