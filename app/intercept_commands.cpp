// proprio intercept ...: hand-eye interception of a moving target (thesis 3.3-3.8;
// docs/results/interception.md).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>

#include "cli.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/planning/figures.hpp"
#include "proprio/planning/interception_trial.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using namespace planning;

// Options shared by the experiment and the sweep.
struct SetupArgs {
  std::string scene;
  std::string cache;
  std::string calib1, calib2;
  std::string transition = "learned";
  int precision_samples = 500;
  int threads = 0;
  double camera_rate = 25;
  int observe_frames = 20;
  double window = 1.5;
};

void add_setup_options(CLI::App* cmd, SetupArgs& a) {
  cmd->add_option("--scene", a.scene,
                  "MJCF scene with the arm and a mocap body 'target' (default: "
                  "data/models/intercept.xml)");
  cmd->add_option("--cache", a.cache,
                  "Trajectory cost cache (default: ~/.cache/proprio/intercept_grid.json); "
                  "recomputed when the arm model or the grid changes");
  cmd->add_option("--calib1", a.calib1, "calib.yml of the left camera (default: built-in pair)");
  cmd->add_option("--calib2", a.calib2, "calib.yml of the right camera");
  cmd->add_option("--transition", a.transition,
                  "Target model: learned (eqs 3.22-3.24, the thesis) or constant-velocity")
      ->check(CLI::IsMember({"learned", "constant-velocity"}));
  cmd->add_option("--precision-samples", a.precision_samples,
                  "Perturbed end points per trajectory for the precision (eq 3.42)")
      ->check(CLI::Range(2, 100000));
  cmd->add_option("--threads", a.threads, "Threads for the trajectory costs (0 = all cores)")
      ->check(CLI::Range(0, 256));
  cmd->add_option("--camera-rate", a.camera_rate, "Camera frame rate, Hz")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--observe-frames", a.observe_frames, "Frames measured before the first plan")
      ->check(CLI::Range(4, 100000));
  cmd->add_option("--window", a.window, "Interception times considered after the move, s")
      ->check(CLI::Range(0.0, 60.0));
}

struct Setup {
  fs::path scene, cache;
  std::unique_ptr<InterceptionSimulator> simulator;
  std::shared_ptr<const GridCostModel> model;
  TrialOptions trial;
};

// Checks everything that can be checked before the (possibly long) trajectory costs.
Setup make_setup(const SetupArgs& a, TrialOptions trial) {
  if (a.calib1.empty() != a.calib2.empty()) {
    throw Error("intercept: give both --calib1 and --calib2, or neither");
  }
  Setup s;
  s.scene = a.scene.empty() ? default_intercept_scene() : fs::path(a.scene);
  s.cache = a.cache.empty() ? default_grid_cache() : fs::path(a.cache);
  const robot::Arm arm = robot::Arm::load(s.scene);
  StereoRig rig = default_stereo_rig();
  if (!a.calib1.empty()) rig = {geometry::read_calib(a.calib1), geometry::read_calib(a.calib2)};
  trial.filter.transition = transition_model_from_string(a.transition);
  trial.camera_rate_hz = a.camera_rate;
  trial.observe_frames = a.observe_frames;
  trial.planner.window = a.window;
  GridCostOptions go;
  check_trial_options(trial, arm.model().opt.timestep, go.grid.duration);
  s.trial = trial;
  go.precision_samples = a.precision_samples;
  go.threads = a.threads;
  s.model = std::make_shared<GridCostModel>(load_or_compute_grid_costs(arm, go, s.cache, true));
  const GridCosts& c = s.model->costs();
  std::printf("trajectory costs: %d of %d trajectories valid (%s, %s)\n", c.summary.valid,
              static_cast<int>(c.points.size()), c.summary.source.c_str(), s.cache.c_str());
  s.simulator = std::make_unique<InterceptionSimulator>(arm, s.model, rig);
  return s;
}

core::Json grid_json(const Setup& s) {
  const GridCosts& c = s.model->costs();
  return {{"scene", s.scene.string()},
          {"cache", s.cache.string()},
          {"key", c.key},
          {"source", c.summary.source},
          {"trajectories", c.points.size()},
          {"valid", c.summary.valid},
          {"precision_samples", c.options.precision_samples},
          {"compute_seconds", c.summary.seconds}};
}

core::Json summary_json(const ExperimentSummary& s) {
  const double ratio = s.mean_predicted_sigma > 0 ? s.mean_miss / s.mean_predicted_sigma : 0.0;
  return {{"trials", s.trials},
          {"executed", s.executed},
          {"not_executed", s.not_executed},
          {"not_planned", s.not_planned},
          {"sigma_px", s.sigma_px},
          {"mean_miss_mm", s.mean_miss * 1e3},
          {"median_miss_mm", s.median_miss * 1e3},
          {"max_miss_mm", s.max_miss * 1e3},
          {"mean_plane_miss_mm", s.mean_plane_miss * 1e3},
          {"mean_predicted_sigma_mm", s.mean_predicted_sigma * 1e3},
          {"mean_first_predicted_sigma_mm", s.mean_first_predicted_sigma * 1e3},
          {"miss_over_predicted_sigma", ratio},
          {"mean_intercept_time_s", s.mean_intercept_time},
          {"mean_plan_ms", s.mean_plan_ms},
          {"max_plan_ms", s.max_plan_ms},
          {"mean_reaims", s.mean_reaims},
          {"mujoco_warning_trials", s.mujoco_warnings}};
}

void print_summary(const char* label, const ExperimentSummary& s) {
  std::printf(
      "%s: %d/%d executed; miss mean %.2f mm, median %.2f mm; predicted std %.2f mm; "
      "interception %.3f s after the plan; plan %.2f ms (max %.2f)\n",
      label, s.executed, s.trials, s.mean_miss * 1e3, s.median_miss * 1e3,
      s.mean_predicted_sigma * 1e3, s.mean_intercept_time, s.mean_plan_ms, s.max_plan_ms);
}

// ---- intercept ---------------------------------------------------------------------------------

struct RunArgs {
  SetupArgs setup;
  double noise_cm = 0;
  int trials = 50;
  std::string prior = "both";
  bool replan = false;
  std::uint64_t seed = 1;
  std::string json;
};

void run_intercept(const RunArgs& a, const Invocation& inv) {
  TrialOptions trial;
  trial.noise_cm = a.noise_cm;
  trial.replan = a.replan;
  trial.planner.mode = prior_mode_from_string(a.prior);
  Setup s = make_setup(a.setup, trial);
  ExperimentOptions eo;
  eo.trial = s.trial;
  eo.trials = a.trials;
  eo.seed = a.seed;
  const ExperimentResult r = run_experiment(*s.simulator, eo, true);
  print_summary("intercept", r.summary);
  for (std::size_t k = 0; k < r.trials.size(); ++k) {
    if (!r.trials[k].executed) {
      std::printf("  trial %zu not executed: %s\n", k + 1, r.trials[k].why_not.c_str());
    }
  }
  core::Json doc = core::result_document("proprio.intercept", 1, inv.provenance(a.seed));
  doc["noise_cm"] = a.noise_cm;
  doc["prior"] = a.prior;
  doc["replan"] = a.replan;
  doc["transition"] = a.setup.transition;
  doc["camera_rate_hz"] = eo.trial.camera_rate_hz;
  doc["observe_frames"] = eo.trial.observe_frames;
  doc["grid"] = grid_json(s);
  doc.update(summary_json(r.summary));
  core::Json trials = core::Json::array();
  for (const TrialResult& t : r.trials) {
    core::Json j = {{"executed", t.executed},
                    {"why_not", t.why_not},
                    {"plan_ms", t.first_plan_ms},
                    {"plans", t.plans},
                    {"reaims", t.reaims}};
    if (t.executed) {
      j["miss_mm"] = t.miss * 1e3;
      j["predicted_sigma_mm"] = t.predicted_sigma * 1e3;
      j["intercept_time_s"] = t.t_intercept - t.t_plan;
      j["psi"] = {t.final_plan.psi.theta, t.final_plan.psi.length, t.final_plan.psi.gamma};
    }
    trials.push_back(std::move(j));
  }
  doc["trial_results"] = std::move(trials);
  write_json_result(a.json, doc);
}

// ---- intercept sweep ---------------------------------------------------------------------------

struct SweepArgs {
  SetupArgs setup;
  std::string out;
  bool overwrite = false;
  int trials = 50;
  std::uint64_t seed = 1;
  std::vector<double> noise = {0, 0.25, 0.5, 1, 1.5, 2, 2.5, 3};
  std::vector<std::string> transitions = {"learned", "constant-velocity"};
  std::vector<double> choice_noise = {0, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 3};
  int choice_draws = 10;
  double figure_noise = 1.5;
};

void run_sweep(const SweepArgs& a, const Invocation& inv) {
  for (double n : a.noise) {
    require(std::isfinite(n) && n >= 0 && n <= 100, "--noise: values must be in [0, 100] cm");
  }
  for (double n : a.choice_noise) {
    require(std::isfinite(n) && n >= 0 && n <= 100,
            "--choice-noise: values must be in [0, 100] cm");
  }
  Setup s = make_setup(a.setup, TrialOptions{});
  core::StagedDirectory dir(a.out, a.overwrite);
  const fs::path stage = dir.staging_path();
  const GridSpec& grid = s.model->grid();
  auto save = [&](const std::string& name, const cv::Mat& img) {
    if (!cv::imwrite((stage / name).string(), img)) {
      throw Error::in_file(fs::path(a.out) / name, "cannot write the image");
    }
  };
  save("energy_grid.png", draw_energy_grid(s.model->costs()));

  core::Json doc = core::result_document("proprio.intercept.sweep", 1, inv.provenance(a.seed));
  doc["trials"] = a.trials;
  doc["noise_cm"] = a.noise;
  doc["prior"] = "both";
  doc["grid"] = grid_json(s);
  core::Json rows = core::Json::array();
  core::Json choices_json = core::Json::array();
  core::ProgressBar bar(a.transitions.size() * a.noise.size() * 2, "sweep", true);
  for (const std::string& tname : a.transitions) {
    TrialOptions base = s.trial;
    base.filter.transition = transition_model_from_string(tname);
    for (double noise : a.noise) {
      for (bool replan : {false, true}) {
        ExperimentOptions eo;
        eo.trial = base;
        eo.trial.noise_cm = noise;
        eo.trial.replan = replan;
        eo.trials = a.trials;
        eo.seed = a.seed;
        const ExperimentResult r = run_experiment(*s.simulator, eo, false);
        core::Json row = {{"transition", tname}, {"noise_cm", noise}, {"replan", replan}};
        row.update(summary_json(r.summary));
        rows.push_back(std::move(row));
        bar.tick();
      }
    }
    // Fig 3-10: one recorded open-loop trial at the figure's noise, on the figures' target.
    {
      TrialOptions o = base;
      o.noise_cm = a.figure_noise;
      o.record = true;
      const TargetMotion target = figure_target(grid, s.simulator->plan_time(o));
      const TrialResult t = s.simulator->run(target, o, a.seed);
      save("interception_" + tname + ".png", draw_interception(t, grid));
    }
    // Fig 3-11: one target, the first plan over repeated noise draws, per prior and noise.
    {
      core::Rng rng(a.seed);
      const double t_plan = s.simulator->plan_time(base);
      const TargetMotion target = figure_target(grid, t_plan);
      std::vector<NoiseChoice> choices;
      for (PriorMode mode : {PriorMode::kBoth, PriorMode::kEnergy, PriorMode::kPrecision}) {
        for (double noise : a.choice_noise) {
          TrialOptions o = base;
          o.noise_cm = noise;
          o.planner.mode = mode;
          NoiseChoice c;
          c.noise_cm = noise;
          c.mode = mode;
          double sum = 0, sum_sq = 0;
          for (int k = 0; k < a.choice_draws; ++k) {
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
          choices_json.push_back({{"transition", tname},
                                  {"prior", to_string(mode)},
                                  {"noise_cm", noise},
                                  {"draws", c.draws},
                                  {"mean_intercept_time_s", c.mean_time},
                                  {"std_intercept_time_s", c.std_time}});
        }
      }
      save("noise_choice_" + tname + ".png", draw_noise_choices(target, t_plan, grid, choices));
    }
  }
  bar.finish();
  doc["rows"] = std::move(rows);
  doc["interception_choices"] = std::move(choices_json);
  write_json_result((stage / "sweep.json").string(), doc);
  dir.commit();
  std::printf("wrote %s (sweep.json, energy_grid.png, interception_*.png, noise_choice_*.png)\n",
              a.out.c_str());
}

}  // namespace

void register_intercept_commands(CLI::App& root, const Invocation& inv) {
  auto* cmd = root.add_subcommand(
      "intercept",
      "Hand-eye interception of a moving target in simulation (thesis 3.3-3.8): learned Kalman "
      "prediction, Bezier trajectories chosen by energy and precision");
  cmd->require_subcommand(0, 1);
  auto run = std::make_shared<RunArgs>();
  add_setup_options(cmd, run->setup);
  cmd->add_option("--noise-cm", run->noise_cm,
                  "Std of the measured 3D position per axis at the workspace centre, cm")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--trials", run->trials, "Number of trials")->check(CLI::Range(1, 1000000));
  cmd->add_option("--prior", run->prior, "both, energy or precision (3.7)")
      ->check(CLI::IsMember({"both", "energy", "precision"}));
  cmd->add_flag("--replan", run->replan,
                "Re-plan with visual feedback as measurements arrive (3.8)");
  cmd->add_option("--seed", run->seed, "Seed of the targets and the noise");
  cmd->add_option("--json", run->json, "Also write the figures as JSON to this file");

  auto sweep = std::make_shared<SweepArgs>();
  auto* sw = cmd->add_subcommand(
      "sweep",
      "Figs 3-8, 3-10 and 3-11 as PNGs and a JSON table over noise, open loop and re-planning");
  add_setup_options(sw, sweep->setup);
  sw->add_option("--out", sweep->out, "Directory to write")->required();
  sw->add_flag("--overwrite", sweep->overwrite, "Replace --out if it exists");
  sw->add_option("--trials", sweep->trials, "Trials per noise level")
      ->check(CLI::Range(1, 1000000));
  sw->add_option("--seed", sweep->seed, "Seed of the targets and the noise");
  sw->add_option("--noise", sweep->noise, "Noise levels, cm (comma separated)")->delimiter(',');
  sw->add_option("--transitions", sweep->transitions, "Target models to compare (comma separated)")
      ->delimiter(',')
      ->check(CLI::IsMember({"learned", "constant-velocity"}));
  sw->add_option("--choice-noise", sweep->choice_noise,
                 "Noise levels of Fig 3-11, cm (comma separated)")
      ->delimiter(',');
  sw->add_option("--choice-draws", sweep->choice_draws, "Noise draws per point of Fig 3-11")
      ->check(CLI::Range(1, 100000));
  sw->add_option("--figure-noise", sweep->figure_noise, "Noise of the Fig 3-10 trial, cm")
      ->check(CLI::Range(0.0, 100.0));

  sw->callback([sweep, &inv] { run_sweep(*sweep, inv); });
  cmd->callback([cmd, sw, run, &inv] {
    (void)cmd;
    if (!sw->parsed()) run_intercept(*run, inv);
  });
}

}  // namespace proprio::app
