// proprio: the command-line tool. Bad usage or bad input: one line on stderr, exit 2.
// Internal failure: one line on stderr, exit 1.

#include <cstdio>

#include "cli.hpp"
#include "exit_status.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/logging.hpp"
#include "proprio/core/version.hpp"
#include "proprio/geometry/opencv_runtime.hpp"
#include "proprio/robot/mujoco_runtime.hpp"

namespace proprio::app {

void JsonFlag::add_to(CLI::App* cmd, const std::string& what) {
  cmd->add_option("--json", path_,
                  "Also write " + what +
                      " as JSON to this file (atomically; never one of the command's inputs or "
                      "outputs)");
}

void JsonFlag::refuse(const std::vector<std::filesystem::path>& others) const {
  if (given()) core::require_output_not_input(path_, others, "--json");
}

void JsonFlag::write(const core::Json& document) const {
  if (given()) core::write_json_atomic(path_, document);
}

core::Provenance Invocation::provenance(std::optional<std::uint64_t> seed) const {
  core::Provenance p = core::Provenance::current(argv, seed);
  p.opencv_version = geometry::opencv_version();
  p.mujoco_version = robot::mujoco_version();
  return p;
}

namespace {

int run(int argc, char** argv) {
  Invocation inv{std::vector<std::string>(argv, argv + argc)};
  CLI::App root{"proprio: a robot arm that learns the objects on a table by pushing them",
                "proprio"};
  root.set_version_flag("--version", std::string("proprio ") + kVersion + " (" + kGitCommit + ")");
  root.require_subcommand(1);
  int verbosity = 0;
  root.add_flag("-v,--verbose", verbosity, "More log output on stderr (repeat for more)");
  root.parse_complete_callback([&verbosity] {
    core::configure_logging(verbosity);
    geometry::set_opencv_log_level(verbosity);
  });
  register_calib_commands(root, inv);
  register_episode_commands(root, inv);
  register_lda_commands(root, inv);
  register_intercept_commands(root, inv);
  register_sim_commands(root, inv);
  register_segment_commands(root, inv);
  register_vocab_commands(root, inv);
  register_recognition_commands(root, inv);
  register_experiment_commands(root, inv);
  register_mot_commands(root, inv);
  register_push_commands(root, inv);
  register_selfsupervise_commands(root, inv);
  register_report_commands(root, inv);
  register_learn_commands(root, inv);

  try {
    root.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return root.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "proprio: %s (see --help)\n", e.what());
    return 2;
  }
  return 0;
}

}  // namespace
}  // namespace proprio::app

int main(int argc, char** argv) {
  return proprio::app::run_with_exit_status([&] { return proprio::app::run(argc, argv); });
}
