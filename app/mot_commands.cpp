// proprio mot ...: the Mixture of Topics object model (thesis 7.1; docs/formats/mot-model.md).
// train: recognition::run_mot_train; classify: recognition::run_mot_classify; update:
// recognition::run_mot_update; info: recognition::run_mot_info. Each command binds its options,
// makes one library call and prints.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/files.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/recognition/topic_localisation.hpp"

namespace proprio::app {
namespace {
using namespace recognition;

// The inputs every mot command that reads views takes: the LDA model, the vocabulary, the
// views (images or episodes) and the feature options (features::ExtractOptions, the same
// description and flags as `recognize`).
void add_source_options(CLI::App* cmd, MotSourceOptions& o) {
  cmd->add_option("--lda-model", o.lda_model, "LDA model file (proprio recognize train)")
      ->required();
  cmd->add_option("--vocabulary", o.vocabulary, "Vocabulary file (proprio vocab build)")
      ->required();
  cmd->add_option("--images", o.images, "Folder-per-object images: an image a view");
  cmd->add_option("--episodes", o.episodes,
                  "Or an episode or a directory of episodes: each object of every --view-step-th "
                  "frame cut out by its ground-truth mask is a view");
  bind_options(cmd, o);
  bind_options(cmd, o.features);
}

// What every mot command that reads views reads: none of it may be one of its outputs.
std::vector<std::filesystem::path> source_inputs(const MotSourceOptions& o) {
  return {o.lda_model, o.vocabulary, o.images, o.episodes};
}

// Refuses each output that is an input or another output of the same run (issue 16).
void require_outputs_distinct(
    const std::vector<std::pair<std::filesystem::path, std::string_view>>& outputs,
    const std::vector<std::filesystem::path>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    std::vector<std::filesystem::path> others = inputs;
    for (std::size_t j = 0; j < outputs.size(); ++j) {
      if (j != i) others.push_back(outputs[j].first);
    }
    core::require_output_not_input(outputs[i].first, others, outputs[i].second);
  }
}

struct TrainArgs {
  MotTrainOptions options;
  JsonFlag json;
};
struct ClassifyArgs {
  MotClassifyOptions options;
  JsonFlag json;
};
struct UpdateArgs {
  MotUpdateOptions options;
  JsonFlag json;
};
struct MapsArgs {
  TopicMapRun run;
};
struct InfoArgs {
  std::string model;
  JsonFlag json;
};

}  // namespace

void register_mot_commands(CLI::App& root, const Invocation& inv) {
  auto* mot = root.add_subcommand(
      "mot", "Mixture of Topics: a Dirichlet over LDA's topic proportions per object (7.1)");
  mot->require_subcommand(1);

  auto t = std::make_shared<TrainArgs>();
  auto* train = mot->add_subcommand("train", "Learn each object's Dirichlet from labelled views");
  add_source_options(train, t->options.source);
  train->add_option("--model", t->options.model, "Mixture of Topics model file to write")
      ->required();
  bind_options(train, t->options);
  // The online rule and its forgetting belong to updates, which train does not make.
  bind_options(train, t->options.mot, FieldFilter{{}, {"update", "forgetting"}});
  t->json.add_to(train, "each object's Dirichlet and the fit");
  train->callback([t, &inv] {
    require_outputs_distinct({{t->options.model, "--model"}, {t->json.path(), "--json"}},
                             source_inputs(t->options.source));
    const MotTrainResult r = run_mot_train(t->options, inv.provenance(t->options.mot.seed));
    std::printf("%s\nmodel: %s\n", r.brief().c_str(), t->options.model.c_str());
    t->json.write(r.document);
  });

  auto c = std::make_shared<ClassifyArgs>();
  auto* classify = mot->add_subcommand(
      "classify",
      "Classify views by Bayes over the objects' Dirichlets (eq 7.3, or by their words: --by)");
  add_source_options(classify, c->options.source);
  classify->add_option("--model", c->options.model, "Mixture of Topics model file")->required();
  classify
      ->add_option("--out", c->options.out,
                   "CSV to write: document, source, frame, truth, class, p_<object>...")
      ->required();
  bind_options(classify, c->options);
  c->json.add_to(classify, "the confusion matrix");
  classify->callback([c, &inv] {
    auto inputs = source_inputs(c->options.source);
    inputs.push_back(c->options.model);
    require_outputs_distinct({{c->options.out, "--out"}, {c->json.path(), "--json"}}, inputs);
    const MotClassifyResult r = run_mot_classify(c->options, inv.provenance());
    std::printf("rows: true object; columns: the Mixture of Topics' object\n%s%s\n",
                r.confusion.format().c_str(), r.brief().c_str());
    c->json.write(r.document);
  });

  auto u = std::make_shared<UpdateArgs>();
  auto* update = mot->add_subcommand(
      "update",
      "Add labelled views to a model's objects: online update of their Dirichlets (8.1.2)");
  add_source_options(update, u->options.source);
  update->add_option("--model", u->options.model, "Mixture of Topics model file to update")
      ->required();
  update->add_option("--out", u->options.out, "Where the updated model goes (may be --model)")
      ->required();
  // Only the online rule's options: the model keeps its prior and smoothing.
  bind_options(update, u->options.mot, FieldFilter{{"update", "forgetting", "seed"}, {}});
  u->json.add_to(update, "the updated objects");
  update->callback([u, &inv] {
    // --out may be --model (the model is read whole before it is replaced), no other input.
    require_outputs_distinct({{u->options.out, "--out"}, {u->json.path(), "--json"}},
                             source_inputs(u->options.source));
    u->json.refuse({u->options.model});
    const MotUpdateResult r = run_mot_update(u->options, inv.provenance(u->options.mot.seed));
    std::printf("%s\nmodel: %s\n", r.brief().c_str(), u->options.out.c_str());
    u->json.write(r.document);
  });

  auto m = std::make_shared<MapsArgs>();
  auto* maps = mot->add_subcommand(
      "maps", "Where each topic's features lie in an image: localisation maps (eqs 7.6-7.7)");
  maps->add_option("--lda-model", m->run.lda_model, "LDA model file")->required();
  maps->add_option("--vocabulary", m->run.vocabulary, "Vocabulary file")->required();
  maps->add_option("--image", m->run.image, "The image")->required();
  maps->add_option("--out", m->run.out, "Directory for topic_<i>.png")->required();
  bind_options(maps, m->run.maps);
  bind_options(maps, m->run.features);
  maps->callback([m] {
    core::require_output_not_input(m->run.out, {m->run.lda_model, m->run.vocabulary, m->run.image},
                                   "--out");
    for (const auto& line : run_topic_maps(m->run)) std::printf("%s\n", line.c_str());
  });

  auto i = std::make_shared<InfoArgs>();
  auto* info = mot->add_subcommand("info", "What a Mixture of Topics model file holds");
  info->add_option("--model", i->model, "Mixture of Topics model file")->required();
  i->json.add_to(info, "it");
  info->callback([i, &inv] {
    i->json.refuse({i->model});
    const MotInfo r = run_mot_info(i->model, inv.provenance());
    std::fputs(r.brief().c_str(), stdout);
    i->json.write(r.document);
  });
}

}  // namespace proprio::app
