// proprio push / proprio evaluate push: bind the options, make the one library call
// (loop::run_push, loop::run_push_evaluation), print its brief, write --json.
#include <cstdio>
#include <memory>
#include <string>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/loop/push_run.hpp"

namespace proprio::app {

namespace {

struct PushArgs {
  loop::PushOptions options;
  std::string json;
};

struct EvaluateArgs {
  loop::PushEvaluationOptions options;
  std::string json;
};

}  // namespace

void register_push_commands(CLI::App& root, const Invocation& inv) {
  auto p = std::make_shared<PushArgs>();
  auto* cmd = root.add_subcommand(
      "push",
      "Plan a push of an object toward a target or the view's edge (thesis 7.2.1) and execute "
      "it on a simulated table; toward a target, look again and push again until within "
      "--tolerance or --max-pushes: the episodes, before/after images and what happened");
  bind_options(cmd, p->options);
  bind_options(cmd, p->options.table);
  bind_options(cmd, p->options.plan);
  cmd->add_option("--json", p->json, "Also write what happened as JSON (push.schema.json)");
  cmd->callback([p, &inv] {
    const loop::PushRunResult r = loop::run_push(p->options, inv.provenance(p->options.table.seed));
    std::printf("%s\n", r.brief().c_str());
    write_json_result(p->json, r.document);
  });

  auto e = std::make_shared<EvaluateArgs>();
  auto* evaluate = root.get_subcommand("evaluate");
  auto* ep = evaluate->add_subcommand(
      "push",
      "Push planning against the simulator's ground truth over seeded tables: distance to target, "
      "intended object moved alone, paths touching others, objects off the table, plan time");
  bind_options(ep, e->options);
  bind_options(ep, e->options.plan, {{}, {"plan_seed"}});
  ep->add_option("--json", e->json, "Also write the figures and every push as JSON");
  ep->callback([e, &inv] {
    const loop::PushEvaluationResult r =
        loop::run_push_evaluation(e->options, inv.provenance(e->options.seed));
    std::printf("%s\n", r.brief().c_str());
    write_json_result(e->json, r.document);
  });
}

}  // namespace proprio::app
