// proprio calib ...: camera geometry (thesis 3.2-3.4).
#include "cli.hpp"

namespace proprio::app {

void register_calib_commands(CLI::App& root, const Invocation& /*inv*/) {
  auto* calib = root.add_subcommand("calib", "Camera calibration and geometry (thesis 3.2-3.4)");
  calib->require_subcommand(1);
}

}  // namespace proprio::app
