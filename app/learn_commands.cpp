// proprio learn: bind the options, make the one library call (loop::run_learn on the simulated
// table), print its brief, write --json.
#include <cstdio>
#include <memory>
#include <string>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/loop/learn.hpp"

namespace proprio::app {

namespace {

struct LearnArgs {
  loop::LearnOptions options;
  bool quiet = false;
  JsonFlag json;
};

}  // namespace

void register_learn_commands(CLI::App& root, const Invocation& inv) {
  auto a = std::make_shared<LearnArgs>();
  auto* cmd = root.add_subcommand(
      "learn",
      "Look, plan, move (thesis Ch 8): on a simulated cluttered table the robot learns the named "
      "objects by itself: it pushes one, segments it by its motion, keeps a word model of it, "
      "recognises it again top-down to plan its next push, moves on to the object least likely "
      "under its models, then builds a vocabulary, LDA and a Mixture of Topics from its own views; "
      "scored on held-out ground-truth views. Writes the run directory --out");
  bind_options(cmd, a->options);
  bind_options(cmd, a->options.features);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  a->json.add_to(cmd, "the result document (learn.json)");
  cmd->callback([a, &inv] {
    a->options.progress = !a->quiet;
    a->json.refuse({a->options.out, a->options.vocabulary, a->options.lda_model});
    const loop::LearnResult r = loop::run_learn(a->options, inv.provenance(a->options.seed));
    std::printf("%s\n", r.brief().c_str());
    a->json.write(r.document);
  });
}

}  // namespace proprio::app
