// proprio selfsupervise: bind the options, make the one library call
// (loop::run_self_supervision_sim), print its brief, write --json.
#include <cstdio>
#include <memory>
#include <string>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/loop/self_supervision_run.hpp"

namespace proprio::app {

namespace {

struct SelfSuperviseArgs {
  loop::SelfSupervisionOptions options;
  bool quiet = false;
  std::string json;
};

}  // namespace

void register_selfsupervise_commands(CLI::App& root, const Invocation& inv) {
  auto a = std::make_shared<SelfSuperviseArgs>();
  auto* cmd = root.add_subcommand(
      "selfsupervise",
      "The robot teaches itself (thesis 7.2 a-d): on a simulated table of the named objects it "
      "singles out one object at a time by pushing the others away, pushes it from many sides to "
      "gather its views, and fits a Mixture of Topics to them; scored against the ground truth "
      "and on held-out views");
  bind_options(cmd, a->options);
  bind_options(cmd, a->options.features);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  cmd->add_option("--json", a->json, "Also write what happened and the scores as JSON");
  cmd->callback([a, &inv] {
    a->options.progress = !a->quiet;
    const loop::SelfSupervisionResult r =
        loop::run_self_supervision_sim(a->options, inv.provenance(a->options.seed));
    std::printf("%s\n", r.brief().c_str());
    write_json_result(a->json, r.document);
  });
}

}  // namespace proprio::app
