// proprio episode ...: the recorded-interaction format.
#include "cli.hpp"

namespace proprio::app {

void register_episode_commands(CLI::App& root, const Invocation& /*inv*/) {
  auto* episode = root.add_subcommand("episode", "Inspect, check and import episodes");
  episode->require_subcommand(1);
}

}  // namespace proprio::app
