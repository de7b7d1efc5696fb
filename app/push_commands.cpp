// proprio push / proprio evaluate push: bind the options, make the one library call
// (loop::run_push, loop::run_push_evaluation), print its brief, write --json.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/loop/push_run.hpp"

namespace proprio::app {

namespace {

struct PushArgs {
  loop::PushOptions options;
  JsonFlag json;
};

struct EvaluateArgs {
  loop::PushEvaluationOptions options;
  JsonFlag json;
};

// `--overwrite` replaces only a directory proprio push wrote (issue 16): one holding push.json (a
// finished run) or episode/episode.json (a run stopped after its first push), or an empty one.
// loop::run_push writes into the directory it is given; a directory of anything else is refused
// before any work.
void require_push_output(const loop::PushOptions& o, const JsonFlag& json) {
  json.refuse({o.out});
  namespace fs = std::filesystem;
  std::error_code ec;
  if (o.out.empty() || !o.overwrite || !fs::exists(o.out, ec)) return;
  if (!fs::is_directory(o.out, ec)) {
    throw Error::in_file(o.out,
                         "is not a directory; --overwrite replaces only a directory "
                         "that proprio push wrote");
  }
  const bool ours = fs::is_regular_file(o.out / "push.json", ec) ||
                    fs::is_regular_file(o.out / "episode" / "episode.json", ec) ||
                    fs::is_empty(o.out, ec);
  if (!ours) {
    throw Error::in_file(o.out,
                         "holds neither push.json nor episode/episode.json: not a "
                         "directory proprio push wrote, so --overwrite does not replace it");
  }
}

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
  p->json.add_to(cmd, "what happened");
  cmd->callback([p, &inv] {
    require_push_output(p->options, p->json);
    const loop::PushRunResult r = loop::run_push(p->options, inv.provenance(p->options.table.seed));
    std::printf("%s\n", r.brief().c_str());
    p->json.write(r.document);
  });

  auto e = std::make_shared<EvaluateArgs>();
  auto* evaluate = root.get_subcommand("evaluate");
  auto* ep = evaluate->add_subcommand(
      "push",
      "Push planning against the simulator's ground truth over seeded tables: distance to target, "
      "intended object moved alone, paths touching others, objects off the table, plan time");
  bind_options(ep, e->options);
  bind_options(ep, e->options.plan, {{}, {"plan_seed"}});
  e->json.add_to(ep, "the figures and every push");
  ep->callback([e, &inv] {
    const loop::PushEvaluationResult r =
        loop::run_push_evaluation(e->options, inv.provenance(e->options.seed));
    std::printf("%s\n", r.brief().c_str());
    e->json.write(r.document);
  });
}

}  // namespace proprio::app
