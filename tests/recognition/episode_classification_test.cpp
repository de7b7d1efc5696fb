// Classifying episodes' frames (thesis 6.1.4, 6.3.3): truth from the ground-truth masks, topics,
// the mapping from labelled views, views cut from frames by the masks, bad input.
#include "proprio/recognition/episode_classification.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "../support/synthetic_episode.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/recognition/experiments.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::recognition {
namespace {
namespace fs = std::filesystem;

// A 10-frame episode: even frames show the "box" (id 1, fine stripes), odd frames the
// "scatter-mug" (id 2, blurred noise), each alone on grey, moving a little.
fs::path write_alternating_episode(const fs::path& dir, bool masks = true) {
  auto info = test::synthetic_info(240, 180, "episode_classification_test", 1);
  info.has_masks = masks;
  const auto cam = test::overhead_camera(300.0, 120.0, 90.0);
  const std::vector<episode::ObjectInfo> objects = {
      {1, "box", episode::ObjectRole::kTarget},
      {2, "scatter-mug", episode::ObjectRole::kDistractor}};
  return test::write_synthetic_episode(dir, info, cam, objects, 10, [masks](int i) {
    cv::Mat img(180, 240, CV_8UC3, cv::Scalar(128, 128, 128));
    cv::Mat1w mask(180, 240, ushort{0});
    const cv::Rect r(40 + 4 * i, 40 + 2 * i, 90, 90);
    cv::Mat tex(90, 90, CV_8UC3);
    if (i % 2 == 0) {
      for (int x = 0; x < 90; ++x) tex.col(x).setTo(cv::Scalar::all((x / 3) % 2 ? 230 : 20));
    } else {
      cv::RNG rng(static_cast<std::uint64_t>(i + 1));
      rng.fill(tex, cv::RNG::UNIFORM, 0, 255);
      cv::GaussianBlur(tex, tex, cv::Size(5, 5), 1.5);
    }
    tex.copyTo(img(r));
    mask(r).setTo(i % 2 == 0 ? 1 : 2);
    test::SyntheticFrame f{img, test::arm_at(i, 25.0, {0.1, 0.0, 0.0}), {}};
    if (masks) f.extras.mask = mask;
    return f;
  });
}

struct Fixture {
  // Shared: the fixture is built once per process and its episodes are read from this directory
  // lazily, so it lives until the process exits and is then removed.
  std::shared_ptr<const test::TempDir> scratch;
  fs::path dir;
  std::vector<episode::Episode> episodes;
  std::optional<features::Vocabulary> vocabulary;
  topics::LdaModel model;
};

// The episode, a 16-word vocabulary from its frames and a K = 2 model learned from them.
const Fixture& fixture() {
  static const Fixture kFixture = [] {
    Fixture x;
    // One directory per process: ctest runs this file's tests in parallel processes.
    x.scratch = std::make_shared<const test::TempDir>("proprio_", "episode_classification_test");
    x.dir = x.scratch->path();
    x.episodes.push_back(episode::read_episode(write_alternating_episode(x.dir / "ep")));
    features::ExtractOptions eo;
    cv::Mat all;
    std::vector<features::Features> docs;
    for (int i = 0; i < 10; ++i) {
      docs.push_back(features::extract_features(x.episodes[0].frame(i), eo));
      all.push_back(docs.back().descriptors);
    }
    features::KmeansOptions k;
    k.words = 16;
    x.vocabulary.emplace(features::build_vocabulary(all, k).vocabulary);
    topics::Corpus corpus(x.vocabulary->size());
    for (const auto& d : docs)
      corpus.add_tokens(features::bag_of_words(*x.vocabulary, d.descriptors));
    topics::OnlineLdaOptions on;
    on.num_topics = 2;
    on.batch_size = 5;
    on.passes = 20;
    x.model = topics::train_online_lda(corpus, on).model;
    return x;
  }();
  return kFixture;
}

TEST(EpisodeClassification, TruthFromMasksAndOneTopicPerObject) {
  const Fixture& f = fixture();
  EpisodeClassifyOptions o;  // whole frames
  const EpisodeClassification r = classify_episodes(f.episodes, f.model, (*f.vocabulary), o);
  ASSERT_EQ(r.documents.size(), 10U);
  EXPECT_EQ(r.classes, (std::vector<std::string>{"box", "mug"}));
  EXPECT_EQ(r.summary.frames, 10);
  EXPECT_EQ(r.summary.empty_documents, 0);
  ASSERT_TRUE(r.by_topic.has_value());
  EXPECT_EQ(r.by_topic->total(), 10);
  for (std::size_t d = 0; d < r.documents.size(); ++d) {
    const ClassifiedDocument& c = r.documents[d];
    EXPECT_EQ(c.frame, static_cast<int>(d));
    EXPECT_EQ(c.truth, c.frame % 2);  // box on even frames, mug on odd ones
    EXPECT_NEAR(r.theta.row(static_cast<Eigen::Index>(d)).sum(), 1.0, 1e-9);
    EXPECT_GT(c.tokens, 0);
  }
  // Stripes and noise share no words: the two objects get different topics, each its own.
  for (const auto& c : r.documents) EXPECT_EQ(c.topic, r.documents[c.frame % 2].topic);
  EXPECT_NE(r.documents[0].topic, r.documents[1].topic);

  o.frame_step = 2;
  const EpisodeClassification even = classify_episodes(f.episodes, f.model, (*f.vocabulary), o);
  ASSERT_EQ(even.documents.size(), 5U);
  EXPECT_EQ(even.classes, (std::vector<std::string>{"box"}));
}

TEST(EpisodeClassification, LabelledViewsFromMasksNameTheTopics) {
  const Fixture& f = fixture();
  const std::vector<std::string> classes = {"mug", "box"};
  // Views from frames 0-3 name the topics; the classification is then scored on all frames.
  const LabelledCorpus views = object_view_corpus(f.episodes, {{0, 1, 2, 3}}, classes,
                                                  (*f.vocabulary), features::ExtractOptions{});
  EXPECT_EQ(views.labels, (std::vector<int>{1, 0, 1, 0}));
  const Evaluation e = evaluate_model(f.model, views, views);
  EXPECT_DOUBLE_EQ(e.classes.accuracy(), 1.0);
  EpisodeClassifyOptions o;
  o.frames.region = FrameRegion::kObjects;
  EpisodeClassification r = classify_episodes(f.episodes, f.model, (*f.vocabulary), o);
  const ConfusionMatrix m = apply_mapping(r, e.mapping, classes);
  EXPECT_EQ(m.rows, classes);
  EXPECT_EQ(m.total(), 10);
  EXPECT_DOUBLE_EQ(m.accuracy(), 1.0);
  for (const auto& c : r.documents) EXPECT_EQ(c.mapped, c.frame % 2 == 0 ? 1 : 0);
  // A view needs min_features features: none of these squares has 10,000.
  EXPECT_EQ(object_view_corpus(f.episodes, {{0, 1}}, classes, (*f.vocabulary),
                               features::ExtractOptions{}, 10000)
                .corpus.num_documents(),
            0U);
}

TEST(EpisodeClassification, EachObjectRegionGivesOneDocumentPerObjectInView) {
  const Fixture& f = fixture();
  EXPECT_EQ(parse_frame_region("each-object"), FrameRegion::kEachObject);
  EXPECT_EQ(to_string(FrameRegion::kEachObject), "each-object");
  FrameDocumentOptions fo;
  fo.region = FrameRegion::kEachObject;
  const auto docs = frame_features(f.episodes[0], 3, fo);
  ASSERT_EQ(docs.size(), 1U);  // only the mug is in frame 3
  fo.region = FrameRegion::kObjects;
  const auto whole_object = frame_features(f.episodes[0], 3, fo);
  // The mask grown by 4 px keeps the patches on the outline as well.
  EXPECT_GT(docs[0].size(), whole_object[0].size());
  // dilate 0: the object's own mask, as the objects region; a larger growth, more features.
  fo.region = FrameRegion::kEachObject;
  fo.dilate = 0;
  EXPECT_EQ(frame_features(f.episodes[0], 3, fo).at(0).size(), whole_object[0].size());
  fo.dilate = 8;
  EXPECT_GT(frame_features(f.episodes[0], 3, fo).at(0).size(), docs[0].size());
  fo.dilate = 101;
  EXPECT_THROW(fo.validate(), Error);
  fo.dilate = -1;
  EXPECT_THROW(fo.validate(), Error);
  fo.dilate = 4;
  fo.objects = {"box"};
  EXPECT_TRUE(frame_features(f.episodes[0], 3, fo).empty());  // the box is not in frame 3
  EpisodeClassifyOptions o;
  o.frames.region = FrameRegion::kEachObject;
  const EpisodeClassification r = classify_episodes(f.episodes, f.model, (*f.vocabulary), o);
  ASSERT_EQ(r.documents.size(), 10U);
  for (const auto& c : r.documents) EXPECT_EQ(c.truth, c.frame % 2);
}

// object_mask: a square of side 21 grown or shrunk by an ellipse of radius 2 is a square of side
// 25 without its corners, or of side 17; a square on the image's edge shrinks from the edge too.
TEST(EpisodeClassification, ObjectMaskGrowsOrShrinksTheObject) {
  cv::Mat ids = cv::Mat::zeros(60, 60, CV_16U);
  ids(cv::Rect(20, 20, 21, 21)).setTo(5);
  ids(cv::Rect(0, 0, 10, 10)).setTo(7);
  EXPECT_EQ(cv::countNonZero(object_mask(ids, 5, 0, 0)), 21 * 21);
  const cv::Mat shrunk = object_mask(ids, 5, 0, 2);
  EXPECT_EQ(cv::countNonZero(shrunk), 17 * 17);
  EXPECT_EQ(cv::countNonZero(shrunk(cv::Rect(22, 22, 17, 17))), 17 * 17);
  const cv::Mat grown = object_mask(ids, 5, 2, 0);
  EXPECT_GT(cv::countNonZero(grown), 21 * 21 + 4 * 21 * 2 - 1);
  EXPECT_LT(cv::countNonZero(grown), 25 * 25);
  EXPECT_EQ(cv::countNonZero(object_mask(ids, 7, 0, 2)), 6 * 6);
  EXPECT_EQ(cv::countNonZero(object_mask(ids, 5, 0, 11)), 0);  // nothing left
  EXPECT_EQ(cv::countNonZero(object_mask(ids, 9, 0, 2)), 0);   // not in the image
  EXPECT_THROW((void)object_mask(ids, 5, 2, 2), Error);
  EXPECT_THROW((void)object_mask(ids, 5, 0, 101), Error);
  EXPECT_THROW((void)object_mask(ids, 5, 0, -1), Error);
  EXPECT_THROW((void)object_mask(ids, 5, -1, 0), Error);
}

// Shrinking the masks (erode) leaves out the grid points near the outline: fewer features, each
// of them inside the shrunk mask; too much shrinking leaves an object no document.
TEST(EpisodeClassification, EachObjectRegionShrunkLeavesTheOutlineOut) {
  const Fixture& f = fixture();
  FrameDocumentOptions fo;
  fo.region = FrameRegion::kEachObject;
  fo.dilate = 0;
  const auto bare = frame_features(f.episodes[0], 3, fo);
  ASSERT_EQ(bare.size(), 1U);
  fo.erode = 4;
  const auto shrunk = frame_features(f.episodes[0], 3, fo);
  ASSERT_EQ(shrunk.size(), 1U);
  EXPECT_GT(shrunk[0].size(), 0);
  EXPECT_LT(shrunk[0].size(), bare[0].size());
  const cv::Mat ids = f.episodes[0].mask(3);
  int id = 0;
  for (const auto& o : f.episodes[0].objects())
    if (cv::countNonZero(ids == o.id) > 0 && o.role != episode::ObjectRole::kArm) id = o.id;
  const cv::Mat m = object_mask(ids, id, 0, 4);
  for (const cv::KeyPoint& k : shrunk[0].keypoints)
    EXPECT_NE(m.at<uchar>(cvRound(k.pt.y), cvRound(k.pt.x)), 0) << k.pt;
  fo.erode = 100;
  EXPECT_TRUE(frame_features(f.episodes[0], 3, fo).empty());
  fo.erode = 101;
  EXPECT_THROW(fo.validate(), Error);
  fo.erode = -1;
  EXPECT_THROW(fo.validate(), Error);
  fo.erode = 2;
  fo.dilate = 4;
  EXPECT_THROW(fo.validate(), Error);
  // The views alike: shrunk, fewer features in all.
  std::vector<int> all(10);
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::string> objects = {"box", "mug"};
  const features::ExtractOptions eo;
  auto features_of = [&](int erode) {
    int n = 0;
    for (const auto& v : object_view_features(f.episodes, {all}, objects, eo, 1, 0, erode).views)
      n += v.size();
    return n;
  };
  EXPECT_LT(features_of(4), features_of(0));
  EXPECT_GT(features_of(4), 0);
  EXPECT_THROW((void)object_view_features(f.episodes, {all}, objects, eo, 1, 4, 2), Error);
}

// The adaptive shrink of the views (erode_min_features): the same views as the bare masks
// (kBareMask), each keeping at least the least features (or all of its bare mask's); a view
// whose fixed shrink keeps that many is the fixed shrink's view, the others keep more.
TEST(EpisodeClassification, AdaptiveShrinkKeepsEnoughFeaturesOfEachView) {
  const Fixture& f = fixture();
  std::vector<int> all(10);
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::string> objects = {"box", "mug"};
  const features::ExtractOptions eo;
  const int least = 5;
  const int erode = 6;
  const LabelledFeatures bare = object_view_features(f.episodes, {all}, objects, eo, least, 0, 0);
  const LabelledFeatures fixed = object_view_features(f.episodes, {all}, objects, eo, least, 0,
                                                      erode, ViewSelection::kBareMask);
  ASSERT_FALSE(fixed.views.empty());
  std::vector<int> sizes;
  for (const auto& v : fixed.views) sizes.push_back(v.size());
  std::sort(sizes.begin(), sizes.end());
  const int k = sizes[sizes.size() / 2] + 1;  // more than half the fixed views keep fewer
  const LabelledFeatures adaptive = object_view_features(f.episodes, {all}, objects, eo, least, 0,
                                                         erode, ViewSelection::kBareMask, k);
  ASSERT_EQ(adaptive.views.size(), bare.views.size());
  ASSERT_EQ(fixed.views.size(), bare.views.size());
  EXPECT_EQ(adaptive.labels, bare.labels);
  int same = 0, more = 0;
  for (std::size_t i = 0; i < adaptive.views.size(); ++i) {
    EXPECT_EQ(adaptive.origins[i].frame, bare.origins[i].frame);
    const int n = adaptive.views[i].size();
    EXPECT_GE(n, std::min(k, bare.views[i].size())) << i;
    EXPECT_LE(n, bare.views[i].size()) << i;
    if (fixed.views[i].size() >= k) {
      ASSERT_EQ(n, fixed.views[i].size()) << i;
      EXPECT_EQ(cv::norm(adaptive.views[i].descriptors, fixed.views[i].descriptors), 0);
      ++same;
    } else if (n > fixed.views[i].size()) {
      ++more;
    }
  }
  EXPECT_GT(same, 0);
  EXPECT_GT(more, 0);
  // Off (0) is the fixed shrink; out of range is an Error.
  const LabelledFeatures off = object_view_features(f.episodes, {all}, objects, eo, least, 0, erode,
                                                    ViewSelection::kBareMask, 0);
  ASSERT_EQ(off.views.size(), fixed.views.size());
  for (std::size_t i = 0; i < off.views.size(); ++i)
    EXPECT_EQ(off.views[i].size(), fixed.views[i].size());
  EXPECT_THROW((void)object_view_features(f.episodes, {all}, objects, eo, least, 0, erode,
                                          ViewSelection::kBareMask, -1),
               Error);
}

// Views chosen by their bare masks (ViewSelection::kBareMask) are the bare masks' views (the same
// episodes, frames and objects, whatever the shrinking), each cut by the shrunk mask: its
// features are those of the shrunk mask's own extraction (possibly none). Each view's origin
// names its frame, its bare mask's area and whether that touches the image's border.
TEST(EpisodeClassification, ViewsChosenByTheBareMasksAreTheBareMasksViews) {
  const Fixture& f = fixture();
  std::vector<int> all(10);
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::string> objects = {"box", "mug"};
  const features::ExtractOptions eo;
  const int least = 5;
  const LabelledFeatures bare = object_view_features(f.episodes, {all}, objects, eo, least, 0, 0);
  const LabelledFeatures chosen =
      object_view_features(f.episodes, {all}, objects, eo, least, 0, 6, ViewSelection::kBareMask);
  const LabelledFeatures shrunk = object_view_features(f.episodes, {all}, objects, eo, 1, 0, 6);
  ASSERT_FALSE(bare.views.empty());
  ASSERT_EQ(chosen.views.size(), bare.views.size());
  ASSERT_EQ(chosen.origins.size(), chosen.views.size());
  ASSERT_EQ(bare.origins.size(), bare.views.size());
  ASSERT_EQ(shrunk.origins.size(), shrunk.views.size());
  EXPECT_EQ(chosen.labels, bare.labels);
  int fewer = 0;
  for (std::size_t i = 0; i < chosen.views.size(); ++i) {
    const ViewOrigin& o = chosen.origins[i];
    EXPECT_EQ(o.episode, bare.origins[i].episode);
    EXPECT_EQ(o.frame, bare.origins[i].frame);
    EXPECT_EQ(o.mask_pixels, bare.origins[i].mask_pixels);
    EXPECT_LE(chosen.views[i].size(), bare.views[i].size());
    if (chosen.views[i].size() < bare.views[i].size()) ++fewer;
    // The shrunk mask's own extraction of the same view (absent when it has no feature).
    std::optional<std::size_t> same;
    for (std::size_t j = 0; j < shrunk.views.size(); ++j)
      if (shrunk.origins[j].frame == o.frame && shrunk.labels[j] == chosen.labels[i]) same = j;
    if (!same) {
      EXPECT_EQ(chosen.views[i].size(), 0);
      continue;
    }
    ASSERT_EQ(chosen.views[i].size(), shrunk.views[*same].size());
    for (int k = 0; k < chosen.views[i].size(); ++k) {
      const auto u = static_cast<std::size_t>(k);
      EXPECT_EQ(chosen.views[i].keypoints[u].pt, shrunk.views[*same].keypoints[u].pt);
    }
    EXPECT_EQ(cv::norm(chosen.views[i].descriptors, shrunk.views[*same].descriptors), 0);
  }
  EXPECT_GT(fewer, 0);
  // The origins: the bare mask's area and border, by hand.
  const episode::Episode& e = f.episodes[0];
  for (std::size_t i = 0; i < bare.views.size(); ++i) {
    const ViewOrigin& o = bare.origins[i];
    EXPECT_EQ(o.episode, 0);
    const cv::Mat ids = e.mask(o.frame);
    int best = -1;
    for (const auto& obj : e.objects()) {
      const cv::Mat m = object_mask(ids, obj.id, 0, 0);
      if (cv::countNonZero(m) != o.mask_pixels) continue;
      best = obj.id;
      const bool border = cv::countNonZero(m.row(0)) + cv::countNonZero(m.row(m.rows - 1)) +
                              cv::countNonZero(m.col(0)) + cv::countNonZero(m.col(m.cols - 1)) >
                          0;
      EXPECT_EQ(o.at_border, border) << o.frame;
    }
    EXPECT_GE(best, 0) << o.frame;
    EXPECT_GT(o.mask_pixels, 0);
  }
}

TEST(EpisodeClassification, ClassNamesDropTheSimulatorsRolePrefixes) {
  EXPECT_EQ(object_class_name("scatter-bike"), "bike");
  EXPECT_EQ(object_class_name("distractor-spirit-level"), "spirit-level");
  EXPECT_EQ(object_class_name("spirit-level"), "spirit-level");
  EXPECT_EQ(object_class_name("my-spirit-level", {"spirit-level"}), "spirit-level");
}

TEST(EpisodeClassification, BadInputIsAnError) {
  const Fixture& f = fixture();
  EpisodeClassifyOptions o;
  // A model over another number of words than the vocabulary.
  topics::LdaModel other = f.model;
  other.lambda = Eigen::MatrixXd::Ones(2, (*f.vocabulary).size() + 1);
  try {
    (void)classify_episodes(f.episodes, other, (*f.vocabulary), o);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("17 words but the vocabulary 16"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)classify_episodes({}, f.model, (*f.vocabulary), o), Error);
  o.frame_step = 0;
  EXPECT_THROW((void)classify_episodes(f.episodes, f.model, (*f.vocabulary), o), Error);
  // Regions that need ground-truth masks, on an episode without them.
  const std::vector<episode::Episode> bare = {
      episode::read_episode(write_alternating_episode(f.dir / "bare", false))};
  o.frame_step = 1;
  o.frames.region = FrameRegion::kObjects;
  try {
    (void)classify_episodes(bare, f.model, (*f.vocabulary), o);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no ground-truth masks"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bare"), std::string::npos) << e.what();
  }
  // Whole frames of an episode without masks: classified, no truth.
  o.frames.region = FrameRegion::kWhole;
  const EpisodeClassification r = classify_episodes(bare, f.model, (*f.vocabulary), o);
  EXPECT_EQ(r.documents.size(), 10U);
  EXPECT_TRUE(r.classes.empty());
  EXPECT_FALSE(r.by_topic.has_value());
  EXPECT_THROW(
      (void)object_view_corpus(bare, {{0}}, {"box"}, (*f.vocabulary), features::ExtractOptions{}),
      Error);
}

// A scatter run small enough for a test: one T, 8 words, a few views per block.
ScatterExperimentOptions small_scatter_options() {
  ScatterExperimentOptions o;
  o.topics = {2};
  o.kmeans.words = 8;
  o.dictionary_frames = 10;
  o.descriptors_per_frame = 30;
  o.online.batch_size = 5;
  o.online.passes = 3;
  o.view_step = 1;
  o.view_block = 2;
  o.view_min_features = 5;
  return o;
}

// Several seeds over one feature extraction give, seed by seed, what a run with that seed alone
// gives: the dictionary, the documents, the views and the confusion matrices.
TEST(ScatterExperiment, SeveralSeedsEqualOneRunPerSeed) {
  const Fixture& f = fixture();
  const ScatterExperimentOptions o = small_scatter_options();
  const std::vector<std::string> objects = {"box", "mug"};
  const std::vector<std::uint64_t> seeds = {3, 4};
  const std::vector<ScatterExperimentResult> many =
      run_scatter_experiments(f.episodes, f.episodes, objects, o, seeds);
  ASSERT_EQ(many.size(), seeds.size());
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    ScatterExperimentOptions one = o;
    one.seed = seeds[i];
    const ScatterExperimentResult r = run_scatter_experiment(f.episodes, f.episodes, objects, one);
    const ScatterExperimentResult& m = many[i];
    EXPECT_EQ(m.frames, r.frames);
    EXPECT_EQ(m.documents, r.documents);
    EXPECT_EQ(m.tokens, r.tokens);
    EXPECT_EQ(m.words, r.words);
    EXPECT_GT(m.mapping_views, 0);
    EXPECT_EQ(m.mapping_views, r.mapping_views);
    EXPECT_EQ(m.test_views, r.test_views);
    ASSERT_TRUE(m.kmeans.has_value() && r.kmeans.has_value());
    EXPECT_EQ(m.kmeans->cost, r.kmeans->cost);
    ASSERT_EQ(m.runs.size(), 1U);
    ASSERT_EQ(r.runs.size(), 1U);
    EXPECT_EQ(m.runs[0].evaluation.topics.counts, r.runs[0].evaluation.topics.counts);
    EXPECT_EQ(m.runs[0].evaluation.classes.counts, r.runs[0].evaluation.classes.counts);
    EXPECT_EQ(m.runs[0].summary.updates, r.runs[0].summary.updates);
  }
  EXPECT_THROW((void)run_scatter_experiments(f.episodes, f.episodes, objects, o, {}), Error);
}

// The masks' growth reaches the run: the each-object frames' documents (frames.dilate) and the
// views (view_dilate). Views cut by the bare masks have at most n0 features; asking for n0 + 1
// leaves none with view_dilate 0, and keeps views grown by 100 px (most of the frame).
TEST(ScatterExperiment, MaskGrowthReachesFramesAndViews) {
  const Fixture& f = fixture();
  ScatterExperimentOptions o = small_scatter_options();
  o.frames.region = FrameRegion::kEachObject;
  const std::vector<std::string> objects = {"box", "mug"};
  const ScatterExperimentResult grown = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  ScatterExperimentOptions bare = o;
  bare.frames.dilate = 0;
  const ScatterExperimentResult r = run_scatter_experiment(f.episodes, f.episodes, objects, bare);
  EXPECT_EQ(r.documents, grown.documents);
  EXPECT_LT(r.tokens, grown.tokens);
  std::vector<int> all(10);
  std::iota(all.begin(), all.end(), 0);
  const LabelledFeatures v =
      object_view_features(f.episodes, {all}, objects, o.view_features, 1, 0);
  ASSERT_FALSE(v.views.empty());
  int n0 = 0;
  for (const auto& x : v.views) n0 = std::max(n0, x.size());
  o.view_min_features = n0 + 1;
  o.view_dilate = 100;
  const ScatterExperimentResult wide = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  EXPECT_GT(wide.mapping_views, 0);
  EXPECT_GT(wide.test_views, 0);
  o.view_dilate = 0;
  EXPECT_THROW((void)run_scatter_experiment(f.episodes, f.episodes, objects, o), Error);
  o.view_dilate = 101;
  EXPECT_THROW(o.validate(), Error);
  // Shrinking reaches the frames' documents (fewer tokens than the bare masks) and the views
  // (shrunk by 100 px, no object has a view left).
  ScatterExperimentOptions shrunk = bare;
  shrunk.frames.erode = 4;
  const ScatterExperimentResult s = run_scatter_experiment(f.episodes, f.episodes, objects, shrunk);
  EXPECT_LT(s.tokens, r.tokens);
  EXPECT_GT(s.tokens, 0);
  shrunk.view_dilate = 0;
  shrunk.view_erode = 100;
  EXPECT_THROW((void)run_scatter_experiment(f.episodes, f.episodes, objects, shrunk), Error);
  shrunk.view_dilate = 4;
  shrunk.view_erode = 2;
  EXPECT_THROW(shrunk.validate(), Error);
  shrunk.view_dilate = 0;
  shrunk.view_erode = 101;
  EXPECT_THROW(shrunk.validate(), Error);
}

// The MoT grid fits the mixture once per component cap: each cap's points carry it, the other
// models carry 1, and the cap-10 points are those of the default grid (10 alone).
TEST(ScatterExperiment, MotGridFitsTheMixtureOncePerComponentCap) {
  const Fixture& f = fixture();
  ScatterExperimentOptions o = small_scatter_options();
  o.mot = true;
  o.mot_smoothing_grid = {0};
  const std::vector<std::string> objects = {"box", "mug"};
  const ScatterExperimentResult one = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  o.mot_grid_components = {2, 10};
  const ScatterExperimentResult two = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  ASSERT_EQ(one.runs.size(), 1U);
  ASSERT_EQ(two.runs.size(), 1U);
  // Per theta source: 2 priors x (2 models + caps), and the 2 + caps fits once more by words.
  EXPECT_EQ(one.runs[0].mot_grid.size(), 2U * (2 * 3 + 3));
  ASSERT_EQ(two.runs[0].mot_grid.size(), 2U * (2 * 4 + 4));
  std::map<int, int> mixtures;
  for (const MotGridPoint& g : two.runs[0].mot_grid) {
    if (g.model.starts_with("mixture")) {
      ++mixtures[g.components];
    } else {
      EXPECT_EQ(g.components, 1) << g.model;
    }
  }
  EXPECT_EQ(mixtures, (std::map<int, int>{{2, 6}, {10, 6}}));
  for (const MotGridPoint& g : one.runs[0].mot_grid) {
    int found = 0;
    for (const MotGridPoint& h : two.runs[0].mot_grid) {
      if (h.source == g.source && h.prior == g.prior && h.model == g.model &&
          h.components == g.components) {
        EXPECT_EQ(h.classes.counts, g.classes.counts) << g.model;
        ++found;
      }
    }
    EXPECT_EQ(found, 1) << g.model << " " << g.components;
  }
  o.mot_grid_components = {1};
  EXPECT_THROW(o.validate(), Error);
  o.mot_grid_components = {};
  EXPECT_THROW(o.validate(), Error);
}

// The grid's word weights: each "-words" point gains one "-words-multinomial" point per weight;
// weight 0 is the "-words" point itself, weight 1 leaves only the word multinomials and the prior
// (the same for every object model of one theta source and prior); the other points are those
// of the grid without weights.
TEST(ScatterExperiment, MotGridPoolsTheWordsWithTheObjectsMultinomials) {
  const Fixture& f = fixture();
  ScatterExperimentOptions o = small_scatter_options();
  o.mot = true;
  o.mot_smoothing_grid = {0};
  const std::vector<std::string> objects = {"box", "mug"};
  const ScatterExperimentResult plain = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  o.mot_grid_word_weights = {0, 0.5, 1};
  const ScatterExperimentResult pooled = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  ASSERT_EQ(plain.runs.size(), 1U);
  ASSERT_EQ(pooled.runs.size(), 1U);
  const std::vector<MotGridPoint>& grid = pooled.runs[0].mot_grid;
  // Per theta source: 2 priors x 3 models, 3 by words, and 3 x 3 pooled.
  ASSERT_EQ(grid.size(), 2U * (2 * 3 + 3 + 3 * 3));
  int words = 0;
  int pooled_points = 0;
  for (const MotGridPoint& g : grid) {
    if (!g.model.ends_with("-words-multinomial")) {
      EXPECT_FALSE(g.word_weight.has_value()) << g.model;
      int found = 0;
      for (const MotGridPoint& h : plain.runs[0].mot_grid) {
        if (h.source == g.source && h.prior == g.prior && h.model == g.model) {
          EXPECT_EQ(h.classes.counts, g.classes.counts) << g.model;
          ++found;
        }
      }
      EXPECT_EQ(found, 1) << g.model;
      words += g.model.ends_with("-words") ? 1 : 0;
      continue;
    }
    ++pooled_points;
    ASSERT_TRUE(g.word_weight.has_value());
    const std::string base = g.model.substr(0, g.model.size() - std::string("-multinomial").size());
    for (const MotGridPoint& h : grid) {
      if (h.source != g.source || h.prior != g.prior) continue;
      if (*g.word_weight == 0 && h.model == base) {
        EXPECT_EQ(h.classes.counts, g.classes.counts) << g.model;
      }
      if (*g.word_weight == 1 && h.word_weight == 1.0) {
        EXPECT_EQ(h.classes.counts, g.classes.counts) << g.model << " " << h.model;
      }
    }
  }
  EXPECT_EQ(words, 6);
  EXPECT_EQ(pooled_points, 18);
  for (const double bad : {-0.1, 1.5, std::nan("")}) {
    o.mot_grid_word_weights = {0.5, bad};
    EXPECT_THROW(o.validate(), Error) << bad;
  }
}

// Each test view carries where it comes from and its object, and the mixture by words' object
// for it (the first component cap, E-step fit, prior from the views): counted, those give that
// grid point's confusion matrix. Views chosen by the bare masks are as many as the bare masks'.
TEST(ScatterExperiment, TestViewsCarryTheirOriginAndTheMixturesObject) {
  const Fixture& f = fixture();
  ScatterExperimentOptions o = small_scatter_options();
  o.mot = true;
  o.mot_smoothing_grid = {0};
  o.mot_grid_components = {3, 10};
  o.view_dilate = 0;
  const std::vector<std::string> objects = {"box", "mug"};
  const ScatterExperimentResult r = run_scatter_experiment(f.episodes, f.episodes, objects, o);
  ASSERT_EQ(r.test_origins.size(), static_cast<std::size_t>(r.test_views));
  ASSERT_EQ(r.test_labels.size(), r.test_origins.size());
  ASSERT_EQ(r.test_features.size(), r.test_origins.size());
  ASSERT_EQ(r.runs.size(), 1U);
  const std::vector<int>& predicted = r.runs[0].mixture_words_predicted;
  ASSERT_EQ(predicted.size(), r.test_origins.size());
  for (const int p : predicted) EXPECT_TRUE(p >= -1 && p < 2) << p;
  const ConfusionMatrix counted = confusion_matrix(r.test_labels, predicted, objects, objects);
  int found = 0;
  for (const MotGridPoint& g : r.runs[0].mot_grid) {
    if (g.source == ThetaSource::kEStep && g.model == "mixture-words" && g.components == 3 &&
        g.prior == topics::MotPrior::kViews) {
      EXPECT_EQ(g.classes.counts, counted.counts);
      ++found;
    }
  }
  EXPECT_EQ(found, 1);
  for (std::size_t i = 0; i < r.test_origins.size(); ++i) {
    EXPECT_GE(r.test_features[i], o.view_min_features);
    EXPECT_GT(r.test_origins[i].mask_pixels, 0);
  }
  // Shrunk by 6 px and chosen by the bare masks: the bare masks' views, each with fewer features
  // (cut by the shrunk mask), some below the least a view needs (which shrinking cuts: that of the
  // smallest bare view).
  std::vector<int> all(10);
  std::iota(all.begin(), all.end(), 0);
  int least = std::numeric_limits<int>::max();
  for (const auto& v :
       object_view_features(f.episodes, {all}, objects, o.view_features, 1, 0, 0).views)
    least = std::min(least, v.size());
  o.view_min_features = least;
  ScatterExperimentOptions shrunk = o;
  shrunk.view_erode = 6;
  shrunk.frames.erode = 6;
  shrunk.frames.dilate = 0;
  shrunk.mot = false;
  shrunk.mot_smoothing_grid = {};
  ScatterExperimentOptions bare = shrunk;
  bare.view_erode = 0;
  bare.frames.erode = 0;
  const ScatterExperimentResult b = run_scatter_experiment(f.episodes, f.episodes, objects, bare);
  shrunk.view_selection = ViewSelection::kBareMask;
  const ScatterExperimentResult c = run_scatter_experiment(f.episodes, f.episodes, objects, shrunk);
  EXPECT_EQ(c.test_views, b.test_views);
  EXPECT_EQ(c.mapping_views, b.mapping_views);
  EXPECT_EQ(c.test_labels, b.test_labels);
  ASSERT_EQ(c.test_features.size(), b.test_features.size());
  int below = 0;
  for (std::size_t i = 0; i < c.test_features.size(); ++i) {
    EXPECT_LT(c.test_features[i], b.test_features[i]);
    EXPECT_EQ(c.test_origins[i].frame, b.test_origins[i].frame);
    if (c.test_features[i] < least) ++below;
  }
  EXPECT_GT(below, 0);
  EXPECT_TRUE(c.runs[0].mixture_words_predicted.empty());
}

// Each seed is handed out as soon as it is done, before the next starts (so a long run that is
// stopped keeps the seeds it finished), equal to what the run returns.
TEST(ScatterExperiment, EachSeedIsHandedOutWhenDone) {
  const Fixture& f = fixture();
  const ScatterExperimentOptions o = small_scatter_options();
  const std::vector<std::string> objects = {"box", "mug"};
  const std::vector<std::uint64_t> seeds = {3, 4, 5};
  std::vector<std::size_t> indices;
  std::vector<ScatterExperimentResult> handed;
  const std::vector<ScatterExperimentResult> all =
      run_scatter_experiments(f.episodes, f.episodes, objects, o, seeds, nullptr, {},
                              [&](std::size_t i, const ScatterExperimentResult& r) {
                                indices.push_back(i);
                                handed.push_back(r);
                              });
  EXPECT_EQ(indices, (std::vector<std::size_t>{0, 1, 2}));
  ASSERT_EQ(handed.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(handed[i].kmeans->cost, all[i].kmeans->cost);
    EXPECT_EQ(handed[i].runs.at(0).evaluation.classes.counts,
              all[i].runs.at(0).evaluation.classes.counts);
  }
  // Stopped after the first seed (the callback throws): the second seed is never started.
  int calls = 0;
  EXPECT_THROW((void)run_scatter_experiments(f.episodes, f.episodes, objects, o, seeds, nullptr, {},
                                             [&](std::size_t, const ScatterExperimentResult&) {
                                               ++calls;
                                               throw Error("stopped");
                                             }),
               Error);
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace proprio::recognition
