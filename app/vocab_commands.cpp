// proprio vocab ...: visual vocabularies (thesis 6.1.2, 6.3.1; docs/formats/vocabulary.md).
// build: SIFT or dense SIFT from a folder-per-class image set, a random sample per image,
// k-means into words; quantize: an image set into a bag-of-words corpus (UCI, one document per
// image) for `proprio lda train`; info: what a vocabulary file holds.
#include <chrono>
#include <cstdio>
#include <memory>
#include <numeric>
#include <opencv2/imgcodecs.hpp>

#include "cli.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/topics/corpus_io.hpp"

namespace proprio::app {
namespace {
using namespace features;
using Clock = std::chrono::steady_clock;

struct ExtractArgs {
  bool dense = false;
  DenseSiftOptions dense_options;
  SiftOptions sift_options;
};

void add_extract_options(CLI::App* cmd, ExtractArgs& e) {
  cmd->add_flag("--dense", e.dense, "Dense SIFT on a grid (7.3.3) instead of SIFT keypoints");
  cmd->add_option("--step", e.dense_options.step, "Dense grid spacing, px")->capture_default_str();
  cmd->add_option("--patch", e.dense_options.size, "Dense SIFT patch side, px")
      ->capture_default_str();
  cmd->add_option("--max-features", e.sift_options.max_features,
                  "SIFT: keep the strongest N per image (0 = all)")
      ->capture_default_str();
}

core::Json extract_json(const ExtractArgs& e) {
  core::Json j{{"dense", e.dense}};
  if (e.dense) {
    j["step"] = e.dense_options.step;
    j["patch"] = e.dense_options.size;
  } else {
    j["max_features"] = e.sift_options.max_features;
  }
  return j;
}

cv::Mat read_grey(const std::filesystem::path& p) {
  cv::Mat img = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
  if (img.empty())
    throw Error::in_file(p, "cannot read the image (missing, empty or not an image)");
  return img;
}

Features extract(const cv::Mat& grey, const ExtractArgs& e) {
  return e.dense ? dense_sift(grey, e.dense_options) : detect_sift(grey, e.sift_options);
}

struct BuildArgs {
  std::string images;
  ExtractArgs extract;
  int per_image = 100;
  KmeansOptions kmeans;
  std::string out;
  std::string json;
  bool progress = true;
};

void run_build(const BuildArgs& a, const Invocation& inv) {
  a.kmeans.validate();
  a.extract.dense_options.validate();
  a.extract.sift_options.validate();
  require(a.per_image >= 0, "--per-image must be >= 0 (0 = every descriptor)");
  const ImageSet set = read_image_set(a.images);
  core::Rng rng(a.kmeans.seed);
  cv::Mat all;
  int without = 0;
  const auto t0 = Clock::now();
  {
    core::ProgressBar bar(set.images.size(), "descriptors", a.progress);
    for (const auto& path : set.images) {
      const Features f = extract(read_grey(path), a.extract);
      bar.tick();
      if (f.empty()) {
        ++without;
        continue;
      }
      const int n = f.descriptors.rows;
      if (a.per_image == 0 || n <= a.per_image) {
        all.push_back(f.descriptors);
        continue;
      }
      // A uniform sample without replacement (partial Fisher-Yates), in grid order.
      std::vector<int> idx(static_cast<std::size_t>(n));
      std::iota(idx.begin(), idx.end(), 0);
      for (int i = 0; i < a.per_image; ++i) {
        std::swap(idx[static_cast<std::size_t>(i)],
                  idx[static_cast<std::size_t>(i) + rng.index(static_cast<std::uint64_t>(n - i))]);
      }
      idx.resize(static_cast<std::size_t>(a.per_image));
      std::sort(idx.begin(), idx.end());
      for (const int i : idx) all.push_back(f.descriptors.row(i));
    }
  }
  const double extract_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (all.empty()) throw Error::in_file(a.images, "no features in any of its images");
  if (all.rows < a.kmeans.words) {
    throw Error::in_file(a.images, std::to_string(all.rows) + " descriptors from " +
                                       std::to_string(set.images.size()) + " images, fewer than " +
                                       std::to_string(a.kmeans.words) + " words");
  }
  const VocabularyResult r = build_vocabulary(all, a.kmeans);
  const auto prov = inv.provenance(a.kmeans.seed);
  write_vocabulary(a.out, r.vocabulary, prov);
  const KmeansSummary& s = r.summary;
  std::printf(
      "%d words from %d descriptors of %zu images (%d without features): extraction %.2f s, "
      "k-means %.2f s, %d iterations (%s), cost %.6g\n",
      r.vocabulary.size(), all.rows, set.images.size(), without, extract_seconds, s.seconds,
      s.iterations, s.termination.c_str(), s.cost);
  core::Json doc = core::result_document("proprio.vocab.build", 1, prov);
  doc["images_dir"] = a.images;
  doc["vocabulary"] = a.out;
  doc["classes"] = set.classes.size();
  doc["images"] = set.images.size();
  doc["images_without_features"] = without;
  doc["features"] = extract_json(a.extract);
  doc["per_image"] = a.per_image;
  doc["words"] = r.vocabulary.size();
  doc["descriptors"] = all.rows;
  doc["extract_seconds"] = extract_seconds;
  doc["kmeans_seconds"] = s.seconds;
  doc["iterations"] = s.iterations;
  doc["termination"] = s.termination;
  doc["cost"] = s.cost;
  doc["empty_clusters_reseeded"] = s.empty_clusters_reseeded;
  doc["tolerance"] = a.kmeans.tolerance;
  doc["seed"] = a.kmeans.seed;
  doc["threads"] = a.kmeans.threads;
  write_json_result(a.json, doc);
}

struct QuantizeArgs {
  std::string vocab;
  std::string images;
  ExtractArgs extract;
  std::string corpus;
  std::string json;
  bool progress = true;
};

void run_quantize(const QuantizeArgs& a, const Invocation& inv) {
  a.extract.dense_options.validate();
  a.extract.sift_options.validate();
  const Vocabulary v = read_vocabulary(a.vocab);
  const ImageSet set = read_image_set(a.images);
  std::vector<std::string> names(static_cast<std::size_t>(v.size()));
  for (int k = 0; k < v.size(); ++k) names[static_cast<std::size_t>(k)] = "v" + std::to_string(k);
  topics::Corpus corpus(v.size(), names);
  std::vector<std::vector<std::optional<double>>> rows;
  std::vector<std::string> files;
  long tokens = 0;
  int without = 0;
  {
    core::ProgressBar bar(set.images.size(), "images", a.progress);
    for (std::size_t i = 0; i < set.images.size(); ++i) {
      const Features f = extract(read_grey(set.images[i]), a.extract);
      bar.tick();
      if (f.descriptors.cols != v.dimension() && !f.empty()) {
        throw Error::in_file(a.vocab, "words of " + std::to_string(v.dimension()) +
                                          " values; the descriptors have " +
                                          std::to_string(f.descriptors.cols));
      }
      // An image without features is an empty document: kept, so that rows match images.
      const auto ids = bag_of_words(v, f.descriptors);
      without += ids.empty() ? 1 : 0;
      tokens += static_cast<long>(ids.size());
      corpus.add_tokens(ids);
      rows.push_back({static_cast<double>(i + 1), static_cast<double>(set.labels[i]),
                      static_cast<double>(ids.size())});
      files.push_back(set.images[i].string());
    }
  }
  topics::write_corpus(corpus, a.corpus, topics::CorpusFormat::kUci);
  // labels.csv beside the corpus: document (1-based, as in docword.txt), class index, tokens.
  std::string csv = core::format_csv({"document", "label", "tokens"}, rows);
  core::write_file_atomic(std::filesystem::path(a.corpus) / "labels.csv", csv);
  std::string classes;
  for (const auto& c : set.classes) classes += c + "\n";
  core::write_file_atomic(std::filesystem::path(a.corpus) / "classes.txt", classes);
  std::printf("%zu documents, %ld tokens over %d words (%d images without features) -> %s\n",
              set.images.size(), tokens, v.size(), without, a.corpus.c_str());
  core::Json doc = core::result_document("proprio.vocab.quantize", 1, inv.provenance());
  doc["vocabulary"] = a.vocab;
  doc["images_dir"] = a.images;
  doc["corpus"] = a.corpus;
  doc["documents"] = set.images.size();
  doc["tokens"] = tokens;
  doc["words"] = v.size();
  doc["images_without_features"] = without;
  doc["classes"] = set.classes;
  doc["features"] = extract_json(a.extract);
  write_json_result(a.json, doc);
}

void run_info(const std::string& vocab, const std::string& json, const Invocation& inv) {
  const Vocabulary v = read_vocabulary(vocab);
  const core::Provenance p = read_vocabulary_provenance(vocab);
  std::printf("%s: %d words of %d values, written %s by proprio %s\n  %s\n", vocab.c_str(),
              v.size(), v.dimension(), p.created_utc.c_str(), p.proprio_version.c_str(),
              p.command_line.c_str());
  core::Json doc = core::result_document("proprio.vocab.info", 1, inv.provenance());
  doc["vocabulary"] = vocab;
  doc["words"] = v.size();
  doc["dimension"] = v.dimension();
  doc["built_by"] = core::to_json(p);
  write_json_result(json, doc);
}

}  // namespace

void register_vocab_commands(CLI::App& root, const Invocation& inv) {
  auto* vocab =
      root.add_subcommand("vocab", "Visual vocabularies: SIFT, k-means, bags of words (Ch 6)");
  vocab->require_subcommand(1);

  auto b = std::make_shared<BuildArgs>();
  auto* build = vocab->add_subcommand("build", "Build a vocabulary by k-means from an image set");
  build->add_option("--images", b->images, "Folder-per-class image set (DIR/<class>/<image>)")
      ->required();
  add_extract_options(build, b->extract);
  build->add_option("--words", b->kmeans.words, "Number of words K")->capture_default_str();
  build->add_option("--per-image", b->per_image, "Descriptors sampled per image (0 = all)")
      ->capture_default_str();
  build->add_option("--max-iterations", b->kmeans.max_iterations, "Lloyd iterations at most")
      ->capture_default_str();
  build
      ->add_option("--tolerance", b->kmeans.tolerance,
                   "Stop when the relative change of the cost falls below this")
      ->capture_default_str();
  build->add_option("--seed", b->kmeans.seed, "Random seed (sampling and k-means++)")
      ->capture_default_str();
  build->add_option("--threads", b->kmeans.threads, "Threads (0 = all cores)")
      ->capture_default_str();
  build->add_option("--out", b->out, "Vocabulary file to write")->required();
  build->add_option("--json", b->json,
                    "Also write descriptors, extract_seconds, kmeans_seconds, iterations, cost");
  build->add_flag("!--no-progress", b->progress, "No progress bar");
  build->callback([b, &inv] { run_build(*b, inv); });

  auto q = std::make_shared<QuantizeArgs>();
  auto* quantize = vocab->add_subcommand(
      "quantize", "Quantise an image set into a UCI bag-of-words corpus (a document per image)");
  quantize->add_option("--vocab", q->vocab, "Vocabulary file")->required();
  quantize->add_option("--images", q->images, "Folder-per-class image set")->required();
  add_extract_options(quantize, q->extract);
  quantize
      ->add_option("--corpus", q->corpus,
                   "Directory to write: docword.txt, vocab.txt, labels.csv, classes.txt")
      ->required();
  quantize->add_option("--json", q->json, "Also write a summary as JSON");
  quantize->add_flag("!--no-progress", q->progress, "No progress bar");
  quantize->callback([q, &inv] { run_quantize(*q, inv); });

  auto i = std::make_shared<std::pair<std::string, std::string>>();
  auto* info = vocab->add_subcommand("info", "Words, dimension and provenance of a vocabulary");
  info->add_option("--vocab", i->first, "Vocabulary file")->required();
  info->add_option("--json", i->second, "Also write them as JSON");
  info->callback([i, &inv] { run_info(i->first, i->second, inv); });
}

}  // namespace proprio::app
