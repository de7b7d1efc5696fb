#include "proprio/features/vocabulary_build.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/geometry/image_file.hpp"

namespace proprio::features {
namespace {

using Clock = std::chrono::steady_clock;

// Read as grey by the decoder, as `vocab build` always has (the vocabulary's bytes depend on it).
cv::Mat read_grey(const std::filesystem::path& p) {
  return geometry::read_image(p, cv::IMREAD_GRAYSCALE);
}

// A uniform sample of `count` rows without replacement (partial Fisher-Yates), in row order.
void append_sample(const cv::Mat& descriptors, int count, core::Rng& rng, cv::Mat& all) {
  const int n = descriptors.rows;
  if (count == 0 || n <= count) {
    all.push_back(descriptors);
    return;
  }
  std::vector<int> idx(static_cast<std::size_t>(n));
  std::iota(idx.begin(), idx.end(), 0);
  for (int i = 0; i < count; ++i) {
    std::swap(idx[static_cast<std::size_t>(i)],
              idx[static_cast<std::size_t>(i) + rng.index(static_cast<std::uint64_t>(n - i))]);
  }
  idx.resize(static_cast<std::size_t>(count));
  std::sort(idx.begin(), idx.end());
  for (const int i : idx) all.push_back(descriptors.row(i));
}

// The extraction options as vocab build has always recorded them ("dense" plus the options of
// that kind), with every described option beside them.
core::Json features_json(const ExtractOptions& o) {
  core::Json j = core::fields_to_json(o);
  j["dense"] = o.kind == FeatureKind::kDense;
  return j;
}

}  // namespace

void VocabularyBuildOptions::validate() const {
  if (images.empty()) throw Error("vocab build: the image set is required");
  core::check_field_bounds(*this, "vocab build");
  features.validate();
  kmeans.validate();
}

std::string VocabularyBuildResult::brief() const {
  char line[320];
  std::snprintf(line, sizeof line,
                "%d words from %d descriptors of %zu images (%d without features): extraction "
                "%.2f s, k-means %.2f s, %d iterations (%s), cost %.6g",
                vocabulary.size(), descriptors, images, images_without_features, extract_seconds,
                kmeans.seconds, kmeans.iterations, kmeans.termination.c_str(), kmeans.cost);
  return line;
}

VocabularyBuildResult run_vocabulary_build(const VocabularyBuildOptions& options,
                                           const core::Provenance& provenance) {
  options.validate();
  const ImageSet set = read_image_set(options.images);
  core::Rng rng(options.kmeans.seed);
  cv::Mat all;
  int without = 0;
  const auto t0 = Clock::now();
  {
    core::ProgressBar bar(set.images.size(), "descriptors", options.progress);
    for (const auto& path : set.images) {
      const Features f = extract_features(read_grey(path), options.features);
      bar.tick();
      if (f.empty()) {
        ++without;
        continue;
      }
      append_sample(f.descriptors, options.per_image, rng, all);
    }
  }
  const double extract_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (all.empty()) throw Error::in_file(options.images, "no features in any of its images");
  if (all.rows < options.kmeans.words) {
    throw Error::in_file(options.images, std::to_string(all.rows) + " descriptors from " +
                                             std::to_string(set.images.size()) +
                                             " images, fewer than " +
                                             std::to_string(options.kmeans.words) + " words");
  }
  VocabularyResult v = build_vocabulary(all, options.kmeans);
  VocabularyBuildResult r{std::move(v.vocabulary), v.summary,   set.classes.size(),
                          set.images.size(),       without,     all.rows,
                          extract_seconds,         core::Json()};
  if (!options.out.empty()) write_vocabulary(options.out, r.vocabulary, provenance);

  core::Json& doc = r.document;
  doc = core::result_document("proprio.vocab.build", 1, provenance);
  doc["images_dir"] = options.images.string();
  doc["vocabulary"] = options.out.string();
  doc["classes"] = r.classes;
  doc["images"] = r.images;
  doc["images_without_features"] = r.images_without_features;
  doc["features"] = features_json(options.features);
  doc["per_image"] = options.per_image;
  doc["words"] = r.vocabulary.size();
  doc["descriptors"] = r.descriptors;
  doc["extract_seconds"] = r.extract_seconds;
  doc["kmeans_seconds"] = r.kmeans.seconds;
  doc["iterations"] = r.kmeans.iterations;
  doc["termination"] = r.kmeans.termination;
  doc["cost"] = r.kmeans.cost;
  doc["empty_clusters_reseeded"] = r.kmeans.empty_clusters_reseeded;
  doc["tolerance"] = options.kmeans.tolerance;
  doc["seed"] = options.kmeans.seed;
  doc["threads"] = options.kmeans.threads;
  return r;
}

}  // namespace proprio::features
