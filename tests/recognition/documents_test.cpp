#include "proprio/recognition/documents.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "../support/synthetic_episode.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/core/random.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/recognition/image_corpus.hpp"

namespace proprio::recognition {
namespace {
namespace fs = std::filesystem;

// A flat grey image with two squares of random texture far apart.
cv::Mat two_patches() {
  cv::Mat img(240, 400, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::Mat noise(70, 70, CV_8UC3);
  cv::RNG rng(5);
  for (const cv::Point at : {cv::Point(30, 80), cv::Point(290, 60)}) {
    rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
    cv::GaussianBlur(noise, noise, cv::Size(3, 3), 0.8);
    noise.copyTo(img(cv::Rect(at, noise.size())));
  }
  return img;
}

TEST(Documents, TwoTexturedPatchesGiveTwoBlobDocuments) {
  const cv::Mat img = two_patches();
  features::ExtractOptions o;
  o.kind = features::FeatureKind::kSift;
  const features::Features f = features::extract_features(img, o);
  ASSERT_GT(f.size(), 20);
  features::KmeansOptions k;
  k.words = 8;
  const auto v = features::build_vocabulary(f.descriptors, k).vocabulary;
  const auto docs = blob_documents(f, img.size(), v);
  ASSERT_EQ(docs.size(), 2U);
  int total = 0;
  for (const auto& d : docs) {
    EXPECT_EQ(d.tokens.size(), d.blob.features.size());
    EXPECT_GE(d.tokens.size(), 5U);
    total += static_cast<int>(d.tokens.size());
    // Each blob lies over one patch.
    const cv::Point c = (d.blob.box.tl() + d.blob.box.br()) / 2;
    EXPECT_TRUE(cv::Rect(10, 60, 110, 110).contains(c) || cv::Rect(270, 40, 110, 110).contains(c))
        << c;
    for (int t : d.tokens) EXPECT_TRUE(t >= 0 && t < 8);
  }
  EXPECT_LE(total, f.size());
  EXPECT_NE(docs[0].blob.box.x < 200, docs[1].blob.box.x < 200);
}

TEST(Documents, MaskKeepsOnlyFeaturesInside) {
  const cv::Mat img = two_patches();
  cv::Mat mask = cv::Mat::zeros(img.size(), CV_8UC1);
  mask(cv::Rect(0, 0, 200, 240)).setTo(255);
  for (features::FeatureKind kind : {features::FeatureKind::kDense, features::FeatureKind::kSift}) {
    features::ExtractOptions o;
    o.kind = kind;
    const features::Features all = features::extract_features(img, o);
    const features::Features left = features::extract_features(img, o, mask);
    ASSERT_GT(left.size(), 0);
    EXPECT_LT(left.size(), all.size());
    EXPECT_EQ(left.descriptors.rows, left.size());
    for (const auto& kp : left.keypoints) EXPECT_LT(kp.pt.x, 200.5F);
  }
  // Dense SIFT at the kept grid points equals the features module's dense SIFT there.
  features::ExtractOptions d;
  d.min_contrast = 0;
  const features::Features all = features::dense_sift(img, d.dense);
  EXPECT_EQ(features::extract_features(img, d).size(), all.size());
  const features::Features left = features::extract_features(img, d, mask);
  int matched = 0;
  for (int i = 0; i < all.size(); ++i) {
    if (all.keypoints[static_cast<std::size_t>(i)].pt != left.keypoints[0].pt) continue;
    EXPECT_LT(cv::norm(all.descriptors.row(i), left.descriptors.row(0)), 1e-3);
    ++matched;
  }
  EXPECT_EQ(matched, 1);
  EXPECT_THROW((void)features::extract_features(img, d, cv::Mat::zeros(10, 10, CV_8UC1)), Error);
}

TEST(Documents, ContrastAndCentreCropKeepTheTexturedCentre) {
  const cv::Mat img = two_patches();  // grey except two textured squares
  features::ExtractOptions o;
  const features::Features f = features::extract_features(img, o);
  ASSERT_GT(f.size(), 0);
  for (const auto& k : f.keypoints) {
    const bool on_patch =
        cv::Rect(22, 72, 86, 86).contains(k.pt) || cv::Rect(282, 52, 86, 86).contains(k.pt);
    EXPECT_TRUE(on_patch) << k.pt;
  }
  o.center_crop = 0.5;  // x in [100, 300): between the patches but for the right one's edge
  const features::Features c = features::extract_features(img, o);
  EXPECT_LT(c.size(), f.size());
  for (const auto& k : c.keypoints) EXPECT_TRUE(k.pt.x >= 100 && k.pt.x < 300) << k.pt;
  o.center_crop = 0;
  EXPECT_THROW((void)features::extract_features(img, o), Error);
}

TEST(Documents, AlphaMaskKeepsTheFeaturesOnTheObject) {
  // sim views --masks writes the object's mask as the alpha channel: with --alpha-mask only the
  // features there make the document (the left patch), the colours under alpha 0 are ignored.
  const proprio::test::TempDir scratch("proprio_alpha_mask_");
  const cv::Mat img = two_patches();
  cv::Mat alpha = cv::Mat::zeros(img.size(), CV_8UC1);
  alpha(cv::Rect(0, 0, 200, 240)).setTo(255);
  cv::Mat bgra;
  cv::merge(std::vector<cv::Mat>{img, alpha}, bgra);
  const fs::path file = scratch.path() / "masked.png";
  ASSERT_TRUE(cv::imwrite(file.string(), bgra));
  features::ExtractOptions o;
  const features::Features all = features::extract_file_features(file, o);
  bool right_patch = false;
  for (const auto& k : all.keypoints) right_patch = right_patch || k.pt.x >= 200;
  EXPECT_TRUE(right_patch);  // without the option the alpha channel is not a mask
  o.alpha_mask = true;
  const features::Features kept = features::extract_file_features(file, o);
  ASSERT_GT(kept.size(), 0);
  EXPECT_LT(kept.size(), all.size());
  for (const auto& k : kept.keypoints) EXPECT_LT(k.pt.x, 200.0F) << k.pt;
  // The same as extract_features with the mask given.
  EXPECT_EQ(kept.size(), features::extract_features(img, o, alpha).size());
  // Grey decoding (vocab build) keeps the same grid points.
  EXPECT_EQ(features::extract_file_features(file, o, /*grey=*/true).size(), kept.size());
  // A picture without alpha: an Error naming it.
  const fs::path plain = scratch.path() / "plain.png";
  ASSERT_TRUE(cv::imwrite(plain.string(), img));
  try {
    (void)features::extract_file_features(plain, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("plain.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no alpha channel"), std::string::npos) << e.what();
  }
}

TEST(Documents, ImagesWithoutFeaturesGiveEmptyDocuments) {
  const cv::Mat flat(100, 100, CV_8UC3, cv::Scalar(50, 50, 50));
  features::ExtractOptions o;
  o.kind = features::FeatureKind::kSift;
  const features::Features f = features::extract_features(flat, o);
  EXPECT_TRUE(f.empty());
  // Flat patches say nothing: dense SIFT drops them unless asked to keep them.
  features::ExtractOptions dense;
  EXPECT_TRUE(features::extract_features(flat, dense).empty());
  dense.min_contrast = 0;
  EXPECT_GT(features::extract_features(flat, dense).size(), 0);
  cv::Mat words(4, 128, CV_32F, cv::Scalar(0));
  const features::Vocabulary v(words);
  EXPECT_TRUE(blob_documents(f, flat.size(), v).empty());
}

TEST(Documents, UnreadableImageNamesTheFile) {
  const fs::path dir = fs::temp_directory_path() / "proprio_recognition_docs";
  fs::create_directories(dir);
  const fs::path bad = dir / "broken.png";
  std::ofstream(bad) << "not a png";
  try {
    (void)features::read_image(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.png"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("not an image proprio reads"), std::string::npos);
  }
  EXPECT_THROW((void)features::read_image(dir / "missing.png"), Error);
  fs::remove_all(dir);
}

// The adaptive shrink works on the object's bounding box padded by erode px: it must give the r
// of shrinking the whole image (the reference below, the code before session 22) on shapes that
// touch the image's edges or not, holes, two parts, and points on half pixels around the box.
TEST(Documents, AdaptiveErosionOnTheBoxIsTheWholeImagesShrink) {
  auto reference = [](const cv::Mat& ids, int id, int erode, int min_features,
                      const std::vector<cv::KeyPoint>& points) {
    if (min_features == 0) return erode;
    for (int r = erode; r > 0; --r) {
      const cv::Mat m = object_mask(ids, id, 0, r);
      int kept = 0;
      for (const cv::KeyPoint& k : points)
        if (on_mask(m, k) && ++kept >= min_features) return r;
    }
    return 0;
  };
  core::Rng rng(22);
  // Uniform integer in [lo, hi].
  auto uniform_int = [&rng](int lo, int hi) {
    const int span = hi - lo + 1;
    return lo + static_cast<int>(rng.index(static_cast<std::uint64_t>(span)));
  };
  int shrunk = 0;
  int bare = 0;
  for (int trial = 0; trial < 60; ++trial) {
    cv::Mat1b ids(48, 64, uchar{0});
    const int cx = uniform_int(-5, 68);
    const int cy = uniform_int(-5, 52);
    cv::ellipse(ids, cv::Point(cx, cy), cv::Size(uniform_int(2, 20), uniform_int(2, 15)),
                uniform_int(0, 179), 0, 360, cv::Scalar(5), cv::FILLED);
    if (trial % 3 == 0) cv::circle(ids, cv::Point(cx, cy), 2, cv::Scalar(0), cv::FILLED);  // hole
    if (trial % 4 == 0)
      cv::rectangle(ids, cv::Rect(uniform_int(0, 60), uniform_int(0, 44), 6, 4), cv::Scalar(5),
                    cv::FILLED);                                          // a second part
    cv::rectangle(ids, cv::Rect(0, 0, 3, 3), cv::Scalar(7), cv::FILLED);  // another object
    std::vector<cv::KeyPoint> points;
    for (int i = 0; i < 400; ++i) {
      // Half pixels too: on_mask rounds them away from zero.
      const float x = static_cast<float>(uniform_int(-4, 136)) / 2.0F;
      const float y = static_cast<float>(uniform_int(-4, 104)) / 2.0F;
      points.emplace_back(cv::Point2f(x, y), 4.0F);
    }
    for (const int erode : {1, 3, 6}) {
      for (const int k : {1, 5, 20, 60, 150}) {
        const int want = reference(ids, 5, erode, k, points);
        EXPECT_EQ(adaptive_erosion(ids, 5, erode, k, points), want)
            << "trial " << trial << " erode " << erode << " k " << k;
        shrunk += want > 0 ? 1 : 0;
        bare += want == 0 ? 1 : 0;
      }
    }
  }
  EXPECT_GT(shrunk, 100);  // both outcomes are exercised
  EXPECT_GT(bare, 100);
  cv::Mat1b none(10, 10, uchar{0});
  EXPECT_EQ(adaptive_erosion(none, 5, 4, 1, {}), 0);  // no such object
}

// The adaptive shrink on a 40 px square with a grid point every 4 px: shrunk by r px the square
// keeps the points in [20 + r, 60 - r) on each axis (100 points bare, 81 for r = 1-3, 64 for 4,
// 49 for 5-7, 36 for 8); the shrink is the largest r <= erode that keeps min_features of them.
TEST(Documents, AdaptiveErosionShrinksOnlyAsFarAsEnoughFeaturesStay) {
  cv::Mat1b ids(100, 100, uchar{0});
  ids(cv::Rect(20, 20, 40, 40)).setTo(3);
  std::vector<cv::KeyPoint> points;
  for (int y = 0; y < 100; y += 4)
    for (int x = 0; x < 100; x += 4) points.emplace_back(cv::Point2f(x, y), 4.0F);
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 0, points), 8);  // off: the fixed shrink
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 36, points), 8);
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 37, points), 7);
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 50, points), 4);
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 64, points), 4);
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 65, points), 3);
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 82, points), 0);  // only the bare mask keeps 82
  EXPECT_EQ(adaptive_erosion(ids, 3, 8, 101, points), 0);
  EXPECT_EQ(adaptive_erosion(ids, 3, 2, 50, points), 2);  // never beyond erode
  EXPECT_EQ(adaptive_erosion(ids, 3, 0, 50, points), 0);
  EXPECT_EQ(adaptive_erosion(ids, 4, 8, 1, points), 0);  // no such object
  // By brute force: the shrunk mask keeps min_features, one pixel more would not.
  auto kept = [&](int r) {
    const cv::Mat m = object_mask(ids, 3, 0, r);
    int n = 0;
    for (const cv::KeyPoint& k : points) n += on_mask(m, k) ? 1 : 0;
    return n;
  };
  for (int k = 1; k <= 101; k += 5) {
    const int r = adaptive_erosion(ids, 3, 8, k, points);
    if (r > 0) {
      EXPECT_GE(kept(r), k) << k;
    }
    for (int q = r + 1; q <= 8; ++q) EXPECT_LT(kept(q), k) << k << " " << q;
  }
  EXPECT_THROW((void)adaptive_erosion(ids, 3, 8, -1, points), Error);
  EXPECT_THROW((void)adaptive_erosion(ids, 3, 8, 10001, points), Error);
  EXPECT_THROW((void)adaptive_erosion(ids, 3, 101, 10, points), Error);
}

TEST(Documents, ParsersRejectUnknownNames) {
  EXPECT_EQ(features::parse_feature_kind("sift"), features::FeatureKind::kSift);
  EXPECT_EQ(parse_frame_region("objects"), FrameRegion::kObjects);
  EXPECT_THROW((void)features::parse_feature_kind("surf"), Error);
  EXPECT_THROW((void)parse_frame_region("everything"), Error);
}

TEST(ImageCorpus, SplitPerClassHoldsOutTheAskedNumber) {
  features::ImageSet set;
  set.classes = {"a", "b"};
  for (int i = 0; i < 10; ++i) {
    std::string name = "x";
    name += std::to_string(i);
    set.images.emplace_back(name);
    set.labels.push_back(i < 6 ? 0 : 1);
  }
  const SetSplit s = split_per_class(set, 2, 1);
  EXPECT_EQ(s.test.size(), 4U);
  EXPECT_EQ(s.train.size(), 6U);
  EXPECT_EQ(images_of(set, s.test, {"b"}).size(), 2U);
  EXPECT_THROW((void)split_per_class(set, 4, 1), Error);  // class b has only 4 images
  EXPECT_THROW((void)images_of(set, s.test, {"c"}), Error);
}

}  // namespace
}  // namespace proprio::recognition

namespace proprio::recognition {
namespace {

// A 6-frame episode: two textured squares (ids 1 "box" target, 2 "scatter-mug") on grey.
fs::path write_two_object_episode(const fs::path& dir) {
  const auto info = test::synthetic_info(320, 240, "documents_test", 1);
  const auto cam = test::overhead_camera(300.0, 160.0, 120.0);
  const std::vector<episode::ObjectInfo> objects = {
      {1, "box", episode::ObjectRole::kTarget},
      {2, "scatter-mug", episode::ObjectRole::kDistractor}};
  return test::write_synthetic_episode(dir, info, cam, objects, 6, [](int i) {
    cv::Mat img(240, 320, CV_8UC3, cv::Scalar(128, 128, 128));
    cv::Mat1w mask(240, 320, ushort{0});
    cv::Mat tex(70, 70, CV_8UC3);
    cv::RNG rng(static_cast<std::uint64_t>(i + 1));
    for (int o = 0; o < 2; ++o) {
      rng.fill(tex, cv::RNG::UNIFORM, 0, 255);
      cv::GaussianBlur(tex, tex, cv::Size(3, 3), 0.8);
      const cv::Rect r(20 + 150 * o + 5 * i, 60 + 3 * i, 70, 70);
      tex.copyTo(img(r));
      mask(r).setTo(o + 1);
    }
    test::SyntheticFrame f{img, test::arm_at(i, 25.0, {0.1, 0.0, 0.0}), {}};
    f.extras.mask = mask;
    return f;
  });
}

TEST(FrameDocuments, RegionsNestAndBadMasksAreNamed) {
  const fs::path dir = fs::temp_directory_path() / "proprio_recognition_frames";
  fs::remove_all(dir);
  const episode::Episode e = episode::read_episode(write_two_object_episode(dir / "ep"));
  FrameDocumentOptions o;
  const cv::Mat frame2 = e.frame(2);
  auto count = [&](FrameRegion r) {
    o.region = r;
    const auto docs = frame_features(e, 2, o);
    // The same from the frame already read (recognize train reads it once for colour words).
    const auto given = frame_features(e, 2, frame2, o);
    EXPECT_EQ(given.size(), docs.size());
    int n = 0;
    for (std::size_t i = 0; i < docs.size(); ++i) {
      n += docs[i].size();
      if (i < given.size()) {
        EXPECT_EQ(given[i].size(), docs[i].size());
        if (!docs[i].descriptors.empty()) {
          EXPECT_EQ(cv::norm(given[i].descriptors, docs[i].descriptors, cv::NORM_L1), 0.0);
        }
      }
    }
    return std::pair<int, std::size_t>(n, docs.size());
  };
  const auto whole = count(FrameRegion::kWhole);
  const auto target = count(FrameRegion::kTarget);
  o.objects = {"box", "mug"};
  const auto both = count(FrameRegion::kObjects);
  o.objects = {"mug"};
  const auto mug = count(FrameRegion::kObjects);
  EXPECT_GT(target.first, 0);
  EXPECT_GT(mug.first, 0);
  EXPECT_EQ(both.first, target.first + mug.first);  // the suffix "-mug" matches scatter-mug
  EXPECT_LE(both.first, whole.first);
  EXPECT_EQ(selected_object_ids(e, {"mug"}), (std::vector<int>{2}));
  EXPECT_EQ(selected_object_ids(e, {}), (std::vector<int>{1, 2}));

  o.features.kind = features::FeatureKind::kSift;
  const auto blobs = count(FrameRegion::kBlobs);
  EXPECT_EQ(blobs.second, 2U);  // one blob per textured square

  o.features.kind = features::FeatureKind::kDense;
  o.region = FrameRegion::kMasks;
  EXPECT_THROW(o.validate(), Error);  // no directory given
  o.masks = dir / "masks";
  fs::create_directories(o.masks);
  try {
    (void)frame_features(e, 2, o);
    FAIL();
  } catch (const Error& err) {
    EXPECT_NE(std::string(err.what()).find("000002.png"), std::string::npos) << err.what();
  }
  cv::Mat1b left(240, 320, uchar{0});
  left(cv::Rect(0, 0, 160, 240)).setTo(255);
  cv::imwrite((o.masks / "000002.png").string(), left);
  const auto in_mask = frame_features(e, 2, o);
  ASSERT_EQ(in_mask.size(), 1U);
  // The box and the textured patches just around its edge are in the left half; the mug is not.
  EXPECT_GE(in_mask[0].size(), target.first);
  EXPECT_LT(in_mask[0].size(), both.first);
  cv::imwrite((o.masks / "000003.png").string(), cv::Mat1b(10, 10, uchar{255}));
  EXPECT_THROW((void)frame_features(e, 3, o), Error);
  fs::remove_all(dir);
}

// The adaptive shrink of each object's frame document: with 1 least feature it is the fixed
// shrink, with more than any object has the bare mask, in between each document keeps at least
// that many features (or all of its bare mask's, when fewer).
TEST(FrameDocuments, AdaptiveShrinkKeepsEnoughFeaturesOfEachObject) {
  const fs::path dir = fs::temp_directory_path() / "proprio_recognition_adaptive";
  fs::remove_all(dir);
  const episode::Episode e = episode::read_episode(write_two_object_episode(dir / "ep"));
  FrameDocumentOptions o;
  o.region = FrameRegion::kEachObject;
  o.dilate = 0;
  const auto bare = frame_features(e, 2, o);
  o.erode = 12;
  const auto fixed = frame_features(e, 2, o);
  ASSERT_EQ(bare.size(), 2U);
  ASSERT_EQ(fixed.size(), 2U);
  auto same = [](const features::Features& a, const features::Features& b) {
    if (a.size() != b.size()) return false;
    for (int k = 0; k < a.size(); ++k) {
      const auto u = static_cast<std::size_t>(k);
      if (a.keypoints[u].pt != b.keypoints[u].pt) return false;
    }
    return cv::norm(a.descriptors, b.descriptors) == 0;
  };
  o.erode_min_features = 1;
  const auto one = frame_features(e, 2, o);
  o.erode_min_features = 10000;
  const auto all = frame_features(e, 2, o);
  ASSERT_EQ(one.size(), 2U);
  ASSERT_EQ(all.size(), 2U);
  const int least = std::min(fixed[0].size(), fixed[1].size()) + 1;
  o.erode_min_features = least;
  const auto some = frame_features(e, 2, o);
  ASSERT_EQ(some.size(), 2U);
  int grew = 0;
  for (std::size_t d = 0; d < 2; ++d) {
    EXPECT_LT(fixed[d].size(), bare[d].size());
    EXPECT_TRUE(same(one[d], fixed[d])) << d;
    EXPECT_TRUE(same(all[d], bare[d])) << d;
    EXPECT_GE(some[d].size(), std::min(least, bare[d].size())) << d;
    EXPECT_LE(some[d].size(), bare[d].size()) << d;
    if (fixed[d].size() >= least) {
      EXPECT_TRUE(same(some[d], fixed[d])) << d;
    }
    if (some[d].size() > fixed[d].size()) ++grew;
  }
  EXPECT_GT(grew, 0);
  o.erode_min_features = -1;
  EXPECT_THROW(o.validate(), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace proprio::recognition
