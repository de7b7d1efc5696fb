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
  std::string json;
};

struct QuantizeArgs {
  recognition::QuantizeImagesOptions options;
  std::string json;
};

void run_info(const std::string& vocab, const std::string& json, const Invocation& inv) {
  const features::VocabularyInfo r = features::run_vocabulary_info(vocab, inv.provenance());
  std::printf("%s\n", r.brief().c_str());
  write_json_result(json, r.document);
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
  build->add_option("--json", b->json,
                    "Also write descriptors, extract_seconds, kmeans_seconds, iterations, cost");
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
    core::require_output_not_input(
        b->json,
        {b->options.out, b->options.images, b->options.checkpointing.checkpoint,
         b->options.checkpointing.resume},
        "--json");
    run_on_world([&](core::Communicator& comm) {
      const auto r =
          features::run_vocabulary_build(b->options, inv.provenance(b->options.kmeans.seed), comm);
      if (comm.rank() != 0) return;
      std::printf("%s\n", r.brief().c_str());
      write_json_result(b->json, r.document);
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
  quantize->add_option("--json", q->json, "Also write a summary as JSON");
  quantize->add_flag("!--no-progress", q->options.progress, "No progress bar");
  quantize->callback([q, &inv] {
    const auto& o = q->options;
    core::require_output_not_input(q->json, {o.corpus, o.vocabulary, o.images}, "--json");
    const auto r = recognition::run_quantize_images(q->options, inv.provenance());
    std::printf("%s -> %s\n", r.brief().c_str(), q->options.corpus.c_str());
    write_json_result(q->json, r.document);
  });

  auto i = std::make_shared<std::pair<std::string, std::string>>();
  auto* info = vocab->add_subcommand("info", "Words, dimension and provenance of a vocabulary");
  info->add_option("--vocab", i->first, "Vocabulary file")->required();
  info->add_option("--json", i->second, "Also write them as JSON");
  info->callback([i, &inv] { run_info(i->first, i->second, inv); });
}

}  // namespace proprio::app
