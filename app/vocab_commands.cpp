// proprio vocab ...: visual vocabularies (thesis 6.1.2, 6.3.1; docs/formats/vocabulary.md).
// build: features::run_vocabulary_build; quantize: recognition::run_quantize_images (an image set
// into a UCI bag-of-words corpus for `proprio lda train`); info: what a vocabulary file holds.
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/files.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/features/vocabulary_build.hpp"
#include "proprio/recognition/image_quantize.hpp"
#include "world.hpp"

namespace proprio::app {
namespace {

// The feature options every command that extracts features takes (one description:
// features::ExtractOptions), and --dense, which `vocab` has always taken for --features dense.
void add_feature_options(CLI::App* cmd, features::ExtractOptions& o) {
  bind_options(cmd, o);
  cmd->add_flag_callback(
      "--dense", [&o] { o.kind = features::FeatureKind::kDense; },
      "The same as --features dense: SIFT on a grid (7.3.3)");
}

struct BuildArgs {
  features::VocabularyBuildOptions options;
  JsonFlag json;
};

struct QuantizeArgs {
  recognition::QuantizeImagesOptions options;
  JsonFlag json;
};

void run_info(const std::string& vocab, const JsonFlag& json, const Invocation& inv) {
  json.refuse({vocab});
  const features::VocabularyInfo r = features::run_vocabulary_info(vocab, inv.provenance());
  std::printf("%s\n", r.brief().c_str());
  json.write(r.document);
}

}  // namespace

void register_vocab_commands(CLI::App& root, const Invocation& inv) {
  auto* vocab =
      root.add_subcommand("vocab", "Visual vocabularies: SIFT, k-means, bags of words (Ch 6)");
  vocab->require_subcommand(1);

  auto b = std::make_shared<BuildArgs>();
  b->options.progress = true;
  auto* build = vocab->add_subcommand("build", "Build a vocabulary by k-means from an image set");
  build
      ->add_option("--images", b->options.images,
                   "Folder-per-class image set (DIR/<class>/<image>)")
      ->required();
  add_feature_options(build, b->options.features);
  bind_options(build, b->options);
  bind_options(build, b->options.kmeans);
  build->add_option("--out", b->options.out, "Vocabulary file to write")->required();
  b->json.add_to(build, "descriptors, extract_seconds, kmeans_seconds, iterations, cost");
  build->add_flag("!--no-progress", b->options.progress, "No progress bar");
  build->add_option("--checkpoint", b->options.checkpointing.checkpoint,
                    "Write a k-means checkpoint here (atomically) every --checkpoint-every "
                    "iterations");
  bind_options(build, b->options.checkpointing);
  build->add_option("--resume", b->options.checkpointing.resume,
                    "Continue k-means from this checkpoint (same images and options; refused "
                    "otherwise)");
  // Under mpirun, data-parallel over the ranks (features/vocabulary_build.hpp); rank 0 prints.
  build->callback([b, &inv] {
    b->json.refuse({b->options.out, b->options.images, b->options.checkpointing.checkpoint,
                    b->options.checkpointing.resume});
    run_on_world([&](core::Communicator& comm) {
      const auto r =
          features::run_vocabulary_build(b->options, inv.provenance(b->options.kmeans.seed), comm);
      if (comm.rank() != 0) return;
      std::printf("%s\n", r.brief().c_str());
      b->json.write(r.document);
    });
  });

  auto q = std::make_shared<QuantizeArgs>();
  q->options.progress = true;
  auto* quantize = vocab->add_subcommand(
      "quantize", "Quantise an image set into a UCI bag-of-words corpus (a document per image)");
  quantize->add_option("--vocab", q->options.vocabulary, "Vocabulary file")->required();
  quantize->add_option("--images", q->options.images, "Folder-per-class image set")->required();
  add_feature_options(quantize, q->options.features);
  quantize
      ->add_option("--corpus", q->options.corpus,
                   "Directory to write: docword.txt, vocab.txt, labels.csv, classes.txt")
      ->required();
  q->json.add_to(quantize, "a summary");
  quantize->add_flag("!--no-progress", q->options.progress, "No progress bar");
  quantize->callback([q, &inv] {
    const auto& o = q->options;
    q->json.refuse({o.corpus, o.vocabulary, o.images});
    const auto r = recognition::run_quantize_images(q->options, inv.provenance());
    std::printf("%s -> %s\n", r.brief().c_str(), q->options.corpus.c_str());
    q->json.write(r.document);
  });

  auto i = std::make_shared<std::pair<std::string, JsonFlag>>();
  auto* info = vocab->add_subcommand("info", "Words, dimension and provenance of a vocabulary");
  info->add_option("--vocab", i->first, "Vocabulary file")->required();
  i->second.add_to(info, "them");
  info->callback([i, &inv] { run_info(i->first, i->second, inv); });
}

}  // namespace proprio::app
