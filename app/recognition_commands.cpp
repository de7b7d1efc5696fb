// proprio recognize ...: objects learned as topics of visual words (thesis Ch 6): LDA from image
// folders or episodes, and classification. The experiments of 6.3 are experiment_commands.cpp.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/recognition/recognize_runs.hpp"

namespace proprio::app {
namespace {
using namespace recognition;

// ---- recognize train / classify ----

struct TrainArgs {
  RecognizeTrainOptions options;
  JsonFlag json;
  bool quiet = false;
};

struct ClassifyArgs {
  RecognizeClassifyOptions options;
  JsonFlag json;
  bool quiet = false;
};

// Where documents come from: --images or --episodes, the region and the feature options.
void add_source_options(CLI::App* cmd, DocumentSource& s, const char* images_help,
                        const char* episodes_help) {
  cmd->add_option("--images", s.images, images_help);
  cmd->add_option("--episodes", s.episodes, episodes_help);
  bind_options(cmd, s);
  cmd->add_option("--objects", s.frames.objects, "Episodes, region objects: object names")
      ->delimiter(',');
  cmd->add_option("--masks", s.frames.masks, "Episodes, region masks: directory of masks");
  // features::ExtractOptions: the same flags as `vocab build` and `vocab quantize`.
  bind_options(cmd, s.frames.features);
}

}  // namespace

void register_recognition_commands(CLI::App& root, const Invocation& inv) {
  auto* rec = root.add_subcommand(
      "recognize", "Objects as topics of visual words: learn and classify (thesis Ch 6)");
  rec->require_subcommand(1);

  auto t = std::make_shared<TrainArgs>();
  auto* train = rec->add_subcommand(
      "train", "Learn LDA from an image folder (an image a document) or from episodes");
  add_source_options(train, t->options.source, "Folder-per-class images (labels are not used)",
                     "Episode directories, or directories of them");
  train->add_option("--vocabulary", t->options.vocabulary, "Vocabulary file (proprio vocab build)")
      ->required();
  train->add_option("--model", t->options.model, "Model file to write")->required();
  bind_options(train, t->options);
  t->options.online.batch_size = 50;
  bind_options(train, t->options.online, {{"topics", "batch", "passes", "seed"}, {}});
  train->add_flag("-q,--quiet", t->quiet, "No progress bar");
  t->json.add_to(train, "a summary");
  train->callback([t, &inv] {
    t->options.progress = !t->quiet;
    const auto& o = t->options;
    std::vector<std::filesystem::path> paths = o.source.episodes;
    for (const auto& q : {o.model, o.vocabulary, o.source.images}) paths.push_back(q);
    t->json.refuse(paths);
    const RecognizeTrainResult r =
        run_recognize_train(t->options, inv.provenance(t->options.online.seed));
    std::fputs(r.brief().c_str(), stdout);
    t->json.write(r.document);
  });

  auto c = std::make_shared<ClassifyArgs>();
  auto* cls = rec->add_subcommand(
      "classify",
      "Classify folder-per-class images or episodes' frames by argmax theta (thesis 6.1.4)");
  cls->add_option("--model", c->options.model, "Model file")->required();
  cls->add_option("--vocabulary", c->options.vocabulary, "The model's vocabulary file")->required();
  add_source_options(cls, c->options.source, "Folder-per-class images to classify",
                     "Episode directories, or directories of them: classify their frames");
  cls->add_option("--map-with", c->options.map_with,
                  "Labelled folder-per-class images that name the topics (never the test images)");
  cls->add_option("--out", c->options.out,
                  "CSV: image, truth, topic, class, theta_0..theta_{K-1} (episodes: episode, "
                  "frame, document, truth, topic, class, theta_k)");
  cls->add_flag("-q,--quiet", c->quiet, "No progress bar");
  c->json.add_to(cls, "the confusion matrices");
  cls->callback([c, &inv] {
    c->options.progress = !c->quiet;
    const auto& o = c->options;
    std::vector<std::filesystem::path> paths = o.source.episodes;
    for (const auto& q : {o.out, o.model, o.vocabulary, o.map_with, o.source.images})
      paths.push_back(q);
    c->json.refuse(paths);
    const RecognizeClassifyResult r = run_recognize_classify(c->options, inv.provenance());
    std::fputs(r.brief().c_str(), stdout);
    c->json.write(r.document);
  });
}

}  // namespace proprio::app
