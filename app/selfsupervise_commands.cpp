// proprio selfsupervise: bind the options, make the one library call
// (loop::run_self_supervision_sim), print its brief, write --json.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/loop/self_supervision_run.hpp"

namespace proprio::app {

namespace {

struct SelfSuperviseArgs {
  loop::SelfSupervisionOptions options;
  bool quiet = false;
  JsonFlag json;
};

// The output directory may be no input, nor hold one; `--overwrite` replaces only a directory
// proprio selfsupervise wrote (issue 16): one holding selfsupervise.json (a finished run) or
// decisions.jsonl (a run stopped on the way), or an empty one. loop::run_self_supervision_sim
// deletes the directory it is told to overwrite: anything else is refused before it is called.
void require_selfsupervise_output(const loop::SelfSupervisionOptions& o, const JsonFlag& json) {
  core::require_output_not_input(o.out, {o.lda_model, o.vocabulary}, "--out");
  json.refuse({o.out, o.lda_model, o.vocabulary});
  namespace fs = std::filesystem;
  std::error_code ec;
  if (o.out.empty() || !o.overwrite || !fs::exists(o.out, ec)) return;
  if (!fs::is_directory(o.out, ec)) {
    throw Error::in_file(o.out,
                         "is not a directory; --overwrite replaces only a directory "
                         "that proprio selfsupervise wrote");
  }
  const bool ours = fs::is_regular_file(o.out / "selfsupervise.json", ec) ||
                    fs::is_regular_file(o.out / "decisions.jsonl", ec) || fs::is_empty(o.out, ec);
  if (!ours) {
    throw Error::in_file(o.out,
                         "holds neither selfsupervise.json nor decisions.jsonl: not a "
                         "directory proprio selfsupervise wrote, so --overwrite does not "
                         "replace it");
  }
}

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
  a->json.add_to(cmd, "what happened and the scores");
  cmd->callback([a, &inv] {
    a->options.progress = !a->quiet;
    require_selfsupervise_output(a->options, a->json);
    const loop::SelfSupervisionResult r =
        loop::run_self_supervision_sim(a->options, inv.provenance(a->options.seed));
    std::printf("%s\n", r.brief().c_str());
    a->json.write(r.document);
  });
}

}  // namespace proprio::app
