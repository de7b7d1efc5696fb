// features::run_vocabulary_build: the library call behind `proprio vocab build`, on opencv-doc
// photographs and on flat images that have no features.
#include "proprio/features/vocabulary_build.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "../support/error_of.hpp"
#include "../support/temp_dir.hpp"

namespace proprio::features {
namespace {
namespace fs = std::filesystem;

fs::path photo_set(const fs::path& root) {
  const fs::path samples = PROPRIO_OPENCV_SAMPLES;
  for (const auto& [cls, file] : std::vector<std::pair<std::string, std::string>>{
           {"fruit", "apple.jpg"}, {"fruit", "orange.jpg"}, {"scene", "graf1.png"}}) {
    fs::create_directories(root / cls);
    fs::copy_file(samples / file, root / cls / file);
  }
  return root;
}

VocabularyBuildOptions small(const fs::path& images) {
  VocabularyBuildOptions o;
  o.images = images;
  o.features.kind = FeatureKind::kDense;
  o.features.dense.step = 16;
  o.per_image = 40;
  o.kmeans.words = 8;
  o.kmeans.seed = 5;
  o.kmeans.threads = 1;
  return o;
}

TEST(VocabularyBuild, SamplesEachImageAndClusters) {
  test::TempDir dir("proprio_vocab_build_");
  VocabularyBuildOptions o = small(photo_set(dir.path() / "images"));
  o.out = dir.path() / "v.vocab";
  const VocabularyBuildResult r = run_vocabulary_build(o, core::Provenance::current({"t"}, 5));
  EXPECT_EQ(r.images, 3U);
  EXPECT_EQ(r.classes, 2U);
  EXPECT_EQ(r.images_without_features, 0);
  EXPECT_EQ(r.descriptors, 3 * 40);  // every photograph has more than 40 grid patches
  EXPECT_EQ(r.vocabulary.size(), 8);
  // The file holds the words returned.
  EXPECT_EQ(cv::norm(read_vocabulary(o.out).words(), r.vocabulary.words(), cv::NORM_INF), 0);
  // The record names the options as described once (features::ExtractOptions).
  EXPECT_EQ(r.document.at("features").at("kind"), "dense");
  EXPECT_EQ(r.document.at("features").at("dense"), true);
  EXPECT_EQ(r.document.at("features").at("step"), 16);
  EXPECT_EQ(r.document.at("descriptors"), 120);
  EXPECT_NE(r.brief().find("8 words from 120 descriptors of 3 images"), std::string::npos)
      << r.brief();

  // Same seed, same words; another seed, another sample.
  o.out.clear();
  EXPECT_EQ(
      cv::norm(run_vocabulary_build(o, {}).vocabulary.words(), r.vocabulary.words(), cv::NORM_INF),
      0);
  o.kmeans.seed = 6;
  EXPECT_GT(
      cv::norm(run_vocabulary_build(o, {}).vocabulary.words(), r.vocabulary.words(), cv::NORM_INF),
      0);
  // per_image 0 takes every descriptor.
  o.per_image = 0;
  EXPECT_GT(run_vocabulary_build(o, {}).descriptors, 3 * 40);
}

TEST(VocabularyBuild, FlatImagesHaveNoFeaturesUnlessContrastIsIgnored) {
  test::TempDir dir("proprio_vocab_build_");
  const fs::path images = photo_set(dir.path() / "images");
  cv::imwrite((images / "scene" / "flat.png").string(), cv::Mat(120, 160, CV_8UC1, cv::Scalar(90)));
  VocabularyBuildOptions o = small(images);
  EXPECT_EQ(run_vocabulary_build(o, {}).images_without_features, 1);
  o.features.min_contrast = 0;  // every grid patch, flat or not
  const VocabularyBuildResult all = run_vocabulary_build(o, {});
  EXPECT_EQ(all.images_without_features, 0);
  EXPECT_EQ(all.descriptors, 4 * 40);
}

TEST(VocabularyBuild, BadInputIsAnErrorNamingIt) {
  test::TempDir dir("proprio_vocab_build_");
  const fs::path images = photo_set(dir.path() / "images");
  VocabularyBuildOptions o = small(images);
  o.kmeans.words = 1000;
  EXPECT_NE(
      test::error_of([&] { (void)run_vocabulary_build(o, {}); }).find("fewer than 1000 words"),
      std::string::npos);
  o = small(images);
  o.per_image = -1;
  EXPECT_EQ(test::error_of([&] { (void)run_vocabulary_build(o, {}); }),
            "vocab build: per_image must be >= 0 (it is -1)");
  o = small(images);
  o.features.center_crop = 0;
  EXPECT_EQ(test::error_of([&] { (void)run_vocabulary_build(o, {}); }),
            "feature options: center_crop must be in (0, 1] (it is 0.0)");
  o = small({});
  EXPECT_EQ(test::error_of([&] { (void)run_vocabulary_build(o, {}); }),
            "vocab build: the image set is required");
  // Only flat images: nothing to cluster.
  const fs::path flat = dir.path() / "flat" / "cls";
  fs::create_directories(flat);
  cv::imwrite((flat / "a.png").string(), cv::Mat(64, 64, CV_8UC1, cv::Scalar(7)));
  o = small(flat.parent_path());
  EXPECT_NE(test::error_of([&] {
              (void)run_vocabulary_build(o, {});
            }).find("no features in any of its images"),
            std::string::npos);
}

}  // namespace
}  // namespace proprio::features
