// proprio intercept ...: hand-eye interception of a moving target (thesis 3.3-3.8;
// docs/results/interception.md). Binds the options, makes the one library call
// (planning::run_interception, planning::run_interception_sweep), prints.
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "proprio/planning/interception_experiment.hpp"

namespace proprio::app {
namespace {
using namespace planning;

// The setup's options as flags (the experiment and the sweep take the same ones).
struct SetupArgs {
  InterceptionSetupOptions options;
  std::string transition = "learned";
};

void add_setup_options(CLI::App* cmd, SetupArgs& a) {
  InterceptionSetupOptions& o = a.options;
  cmd->add_option("--scene", o.scene,
                  "MJCF scene with the arm and a mocap body 'target' (default: "
                  "data/models/intercept.xml)");
  cmd->add_option("--cache", o.cache,
                  "Trajectory cost cache (default: ~/.cache/proprio/intercept_grid.json); "
                  "recomputed when the arm model or the grid changes");
  cmd->add_option("--calib1", o.calib_left,
                  "calib.yml of the left camera (default: built-in pair)");
  cmd->add_option("--calib2", o.calib_right, "calib.yml of the right camera");
  cmd->add_option("--transition", a.transition,
                  "Target model: learned (eqs 3.22-3.24, the thesis) or constant-velocity")
      ->check(CLI::IsMember({"learned", "constant-velocity"}));
  cmd->add_option("--precision-samples", o.precision_samples,
                  "Perturbed end points per trajectory for the precision (eq 3.42)")
      ->check(CLI::Range(2, 100000));
  cmd->add_option("--threads", o.threads, "Threads for the trajectory costs (0 = all cores)")
      ->check(CLI::Range(0, 256));
  cmd->add_option("--camera-rate", o.camera_rate_hz, "Camera frame rate, Hz")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--observe-frames", o.observe_frames, "Frames measured before the first plan")
      ->check(CLI::Range(4, 100000));
  cmd->add_option("--window", o.window, "Interception times considered after the move, s")
      ->check(CLI::Range(0.0, 60.0));
}

InterceptionSetupOptions setup_options(const SetupArgs& a) {
  InterceptionSetupOptions o = a.options;
  o.transition = transition_model_from_string(a.transition);
  o.progress = true;
  return o;
}

struct RunArgs {
  SetupArgs setup;
  InterceptionRunOptions options;
  std::string prior = "both";
  JsonFlag json;
};

struct SweepArgs {
  SetupArgs setup;
  InterceptionSweepOptions options;
  std::vector<std::string> transitions = {"learned", "constant-velocity"};
};

void run_intercept(RunArgs& a, const Invocation& inv) {
  a.options.setup = setup_options(a.setup);
  a.options.prior = prior_mode_from_string(a.prior);
  const InterceptionSetupOptions& s = a.options.setup;
  a.json.refuse({s.scene, s.cache, s.calib_left, s.calib_right});
  const InterceptionRunResult r = run_interception(a.options, inv.provenance(a.options.seed));
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
}

void run_sweep(SweepArgs& a, const Invocation& inv) {
  a.options.setup = setup_options(a.setup);
  a.options.transitions.clear();
  for (const std::string& t : a.transitions) {
    a.options.transitions.push_back(transition_model_from_string(t));
  }
  const InterceptionSweepResult r =
      run_interception_sweep(a.options, inv.provenance(a.options.seed));
  std::fputs(r.brief().c_str(), stdout);
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
  cmd->add_option("--noise-cm", run->options.noise_cm,
                  "Std of the measured 3D position per axis at the workspace centre, cm")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--trials", run->options.trials, "Number of trials")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--prior", run->prior, "both, energy or precision (3.7)")
      ->check(CLI::IsMember({"both", "energy", "precision"}));
  cmd->add_flag("--replan", run->options.replan,
                "Re-plan with visual feedback as measurements arrive (3.8)");
  cmd->add_option("--seed", run->options.seed, "Seed of the targets and the noise");
  run->json.add_to(cmd, "the figures");

  auto sweep = std::make_shared<SweepArgs>();
  auto* sw = cmd->add_subcommand(
      "sweep",
      "Figs 3-8, 3-10 and 3-11 as PNGs and a JSON table over noise, open loop and re-planning");
  add_setup_options(sw, sweep->setup);
  InterceptionSweepOptions& so = sweep->options;
  sw->add_option("--out", so.out, "Directory to write")->required();
  sw->add_flag("--overwrite", so.overwrite, "Replace --out if it exists");
  sw->add_option("--trials", so.trials, "Trials per noise level")->check(CLI::Range(1, 1000000));
  sw->add_option("--seed", so.seed, "Seed of the targets and the noise");
  sw->add_option("--noise", so.noise, "Noise levels, cm (comma separated)")->delimiter(',');
  sw->add_option("--transitions", sweep->transitions, "Target models to compare (comma separated)")
      ->delimiter(',')
      ->check(CLI::IsMember({"learned", "constant-velocity"}));
  sw->add_option("--choice-noise", so.choice_noise,
                 "Noise levels of Fig 3-11, cm (comma separated)")
      ->delimiter(',');
  sw->add_option("--choice-draws", so.choice_draws, "Noise draws per point of Fig 3-11")
      ->check(CLI::Range(1, 100000));
  sw->add_option("--figure-noise", so.figure_noise, "Noise of the Fig 3-10 trial, cm")
      ->check(CLI::Range(0.0, 100.0));

  sw->callback([sweep, &inv] { run_sweep(*sweep, inv); });
  cmd->callback([cmd, sw, run, &inv] {
    (void)cmd;
    if (!sw->parsed()) run_intercept(*run, inv);
  });
}

}  // namespace proprio::app
