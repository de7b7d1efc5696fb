#include "proprio/planning/interception_experiment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/planning/figures.hpp"

namespace proprio::planning {
namespace fs = std::filesystem;

void InterceptionSetupOptions::validate() const {
  require(calib_left.empty() == calib_right.empty(),
          "intercept: give both --calib1 and --calib2, or neither");
  require(precision_samples >= 2 && precision_samples <= 100000,
          "intercept: precision_samples must be in [2, 100000]");
  require(threads >= 0 && threads <= 256, "intercept: threads must be in [0, 256]");
  require(std::isfinite(camera_rate_hz) && camera_rate_hz > 0,
          "intercept: camera_rate_hz must be > 0");
  require(observe_frames >= 4 && observe_frames <= 100000,
          "intercept: observe_frames must be in [4, 100000]");
  require(std::isfinite(window) && window >= 0 && window <= 60,
          "intercept: window must be in [0, 60] s");
}

GridRecord InterceptionSetup::grid_record() const {
  const GridCosts& c = model->costs();
  return {scene,
          cache,
          c.key,
          c.summary.source,
          c.points.size(),
          c.summary.valid,
          c.options.precision_samples,
          c.summary.seconds};
}

std::string InterceptionSetup::brief() const {
  const GridCosts& c = model->costs();
  return fmt::format("trajectory costs: {} of {} trajectories valid ({}, {})\n", c.summary.valid,
                     c.points.size(), c.summary.source, cache.string());
}

InterceptionSetup make_interception_setup(const InterceptionSetupOptions& options,
                                          TrialOptions trial) {
  options.validate();
  InterceptionSetup s;
  s.scene = options.scene.empty() ? default_intercept_scene() : options.scene;
  s.cache = options.cache.empty() ? default_grid_cache() : options.cache;
  const robot::Arm arm = robot::Arm::load(s.scene);
  StereoRig rig = default_stereo_rig();
  if (!options.calib_left.empty()) {
    rig = {geometry::read_calib(options.calib_left), geometry::read_calib(options.calib_right)};
  }
  trial.filter.transition = options.transition;
  trial.camera_rate_hz = options.camera_rate_hz;
  trial.observe_frames = options.observe_frames;
  trial.planner.window = options.window;
  GridCostOptions go;
  check_trial_options(trial, arm.model().opt.timestep, go.grid.duration);
  s.trial = trial;
  go.precision_samples = options.precision_samples;
  go.threads = options.threads;
  s.model = std::make_shared<GridCostModel>(
      load_or_compute_grid_costs(arm, go, s.cache, options.progress));
  s.simulator = std::make_unique<InterceptionSimulator>(arm, s.model, rig);
  return s;
}

TrialRow TrialRow::of(const TrialResult& t) {
  TrialRow r{t.executed, t.why_not, t.first_plan_ms, t.plans, t.reaims, {}, {}, {}, {}};
  if (t.executed) {
    r.miss_mm = t.miss * 1e3;
    r.predicted_sigma_mm = t.predicted_sigma * 1e3;
    r.intercept_time_s = t.t_intercept - t.t_plan;
    r.psi = std::vector<double>{t.final_plan.psi.theta, t.final_plan.psi.length,
                                t.final_plan.psi.gamma};
  }
  return r;
}

namespace {

void require_noise_levels(const std::vector<double>& levels, const char* what) {
  for (double n : levels) {
    require(std::isfinite(n) && n >= 0 && n <= 100,
            fmt::format("{}: values must be in [0, 100] cm", what));
  }
}

}  // namespace

void InterceptionRunOptions::validate() const {
  setup.validate();
  require(std::isfinite(noise_cm) && noise_cm >= 0 && noise_cm <= 100,
          "intercept: noise_cm must be in [0, 100]");
  require(trials >= 1 && trials <= 1000000, "intercept: trials must be in [1, 1000000]");
}

InterceptionRunResult run_interception(const InterceptionRunOptions& options,
                                       const core::Provenance& provenance) {
  options.validate();
  TrialOptions trial;
  trial.noise_cm = options.noise_cm;
  trial.replan = options.replan;
  trial.planner.mode = options.prior;
  const InterceptionSetup s = make_interception_setup(options.setup, trial);
  InterceptionRunResult r;
  r.setup_brief = s.brief();
  ExperimentOptions eo;
  eo.trial = s.trial;
  eo.trials = options.trials;
  eo.seed = options.seed;
  r.experiment = run_experiment(*s.simulator, eo, options.setup.progress);
  r.noise_cm = options.noise_cm;
  r.prior = to_string(options.prior);
  r.replan = options.replan;
  r.transition = to_string(options.setup.transition);
  r.camera_rate_hz = eo.trial.camera_rate_hz;
  r.observe_frames = eo.trial.observe_frames;
  r.grid = s.grid_record();
  for (const TrialResult& t : r.experiment.trials) r.trial_results.push_back(TrialRow::of(t));
  r.document = core::result_document("proprio.intercept", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

std::string InterceptionRunResult::brief() const {
  const ExperimentSummary& s = experiment.summary;
  std::string b = setup_brief;
  b += fmt::format(
      "intercept: {}/{} executed; miss mean {:.2f} mm, median {:.2f} mm; predicted std {:.2f} mm; "
      "interception {:.3f} s after the plan; plan {:.2f} ms (max {:.2f})\n",
      s.executed, s.trials, s.mean_miss * 1e3, s.median_miss * 1e3, s.mean_predicted_sigma * 1e3,
      s.mean_intercept_time, s.mean_plan_ms, s.max_plan_ms);
  for (std::size_t k = 0; k < experiment.trials.size(); ++k) {
    if (!experiment.trials[k].executed) {
      b += fmt::format("  trial {} not executed: {}\n", k + 1, experiment.trials[k].why_not);
    }
  }
  return b;
}

void InterceptionSweepOptions::validate() const {
  setup.validate();
  require(!out.empty(), "intercept sweep: no output directory given");
  require(trials >= 1 && trials <= 1000000, "intercept sweep: trials must be in [1, 1000000]");
  require_noise_levels(noise, "--noise");
  require_noise_levels(choice_noise, "--choice-noise");
  require(choice_draws >= 1 && choice_draws <= 100000,
          "intercept sweep: choice_draws must be in [1, 100000]");
  require(std::isfinite(figure_noise) && figure_noise >= 0 && figure_noise <= 100,
          "intercept sweep: figure_noise must be in [0, 100]");
}

namespace {

// Fig 3-11: one target, the first plan over repeated noise draws, per prior and noise level.
std::vector<NoiseChoice> noise_choices(const InterceptionSetup& s, const TrialOptions& base,
                                       const InterceptionSweepOptions& options,
                                       const TargetMotion& target, double t_plan,
                                       std::vector<NoiseChoiceRecord>& records) {
  core::Rng rng(options.seed);
  std::vector<NoiseChoice> choices;
  for (PriorMode mode : {PriorMode::kBoth, PriorMode::kEnergy, PriorMode::kPrecision}) {
    for (double noise : options.choice_noise) {
      TrialOptions o = base;
      o.noise_cm = noise;
      o.planner.mode = mode;
      NoiseChoice c;
      c.noise_cm = noise;
      c.mode = mode;
      double sum = 0, sum_sq = 0;
      for (int k = 0; k < options.choice_draws; ++k) {
        const InterceptionPlan p = s.simulator->first_plan(target, o, rng.next_seed());
        if (!p.feasible) continue;
        const double dt = p.t_intercept - t_plan;
        sum += dt;
        sum_sq += dt * dt;
        ++c.draws;
      }
      if (c.draws > 0) {
        c.mean_time = sum / c.draws;
        c.std_time = std::sqrt(std::max(0.0, sum_sq / c.draws - c.mean_time * c.mean_time));
      }
      choices.push_back(c);
      records.push_back({to_string(base.filter.transition), to_string(mode), noise, c.draws,
                         c.mean_time, c.std_time});
    }
  }
  return choices;
}

}  // namespace

InterceptionSweepResult run_interception_sweep(const InterceptionSweepOptions& options,
                                               const core::Provenance& provenance) {
  options.validate();
  const InterceptionSetup s = make_interception_setup(options.setup);
  InterceptionSweepResult r;
  r.setup_brief = s.brief();
  r.out = options.out;
  core::StagedDirectory dir(options.out, options.overwrite);
  const fs::path stage = dir.staging_path();
  const GridSpec& grid = s.model->grid();
  auto save = [&](const std::string& name, const cv::Mat& img) {
    if (!cv::imwrite((stage / name).string(), img)) {
      throw Error::in_file(options.out / name, "cannot write the image");
    }
    r.files.push_back(name);
  };
  save("energy_grid.png", draw_energy_grid(s.model->costs()));

  r.trials = options.trials;
  r.noise_cm = options.noise;
  r.grid = s.grid_record();
  core::ProgressBar bar(options.transitions.size() * options.noise.size() * 2, "sweep",
                        options.setup.progress);
  for (const TransitionModel transition : options.transitions) {
    const std::string tname = to_string(transition);
    TrialOptions base = s.trial;
    base.filter.transition = transition;
    for (double noise : options.noise) {
      for (bool replan : {false, true}) {
        ExperimentOptions eo;
        eo.trial = base;
        eo.trial.noise_cm = noise;
        eo.trial.replan = replan;
        eo.trials = options.trials;
        eo.seed = options.seed;
        const ExperimentResult e = run_experiment(*s.simulator, eo, false);
        r.rows.push_back({tname, noise, replan, e.summary});
        bar.tick();
      }
    }
    // Fig 3-10: one recorded open-loop trial at the figure's noise, on the figures' target.
    {
      TrialOptions o = base;
      o.noise_cm = options.figure_noise;
      o.record = true;
      const TargetMotion target = figure_target(grid, s.simulator->plan_time(o));
      const TrialResult t = s.simulator->run(target, o, options.seed);
      save("interception_" + tname + ".png", draw_interception(t, grid));
    }
    const double t_plan = s.simulator->plan_time(base);
    const TargetMotion target = figure_target(grid, t_plan);
    const std::vector<NoiseChoice> choices =
        noise_choices(s, base, options, target, t_plan, r.interception_choices);
    save("noise_choice_" + tname + ".png", draw_noise_choices(target, t_plan, grid, choices));
  }
  bar.finish();
  r.document = core::result_document("proprio.intercept.sweep", 1, provenance);
  core::fields_into_json(r, r.document);
  core::write_json_atomic(stage / "sweep.json", r.document);
  r.files.insert(r.files.begin(), "sweep.json");
  dir.commit();
  r.message = core::first_line(r.brief());
  return r;
}

std::string InterceptionSweepResult::brief() const {
  return setup_brief +
         fmt::format(
             "wrote {} (sweep.json, energy_grid.png, interception_*.png, noise_choice_*.png)\n",
             out.string());
}

}  // namespace proprio::planning
