// proprio recognize ... and proprio experiment ...: run the built tool on a tiny image set made
// here (crops of opencv-doc photographs, one photograph per class) and on a synthetic episode
// with ground-truth masks; check the printed matrices, the JSON against its schema, and bad input.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>

#include "../support/schema_check.hpp"
#include "../support/synthetic_episode.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace {
namespace fs = std::filesystem;
using namespace proprio;

struct CliRun {
  int code = 0;
  std::string out;
};

CliRun run(const std::string& args) {
  const std::string cmd = test::cli_path() + " " + args + " 2>&1";
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (fgets(buf, sizeof buf, p) != nullptr) r.out += buf;
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// NOLINTNEXTLINE(readability-identifier-naming)
const char* kPhotos[] = {"baboon.jpg", "fruits.jpg", "building.jpg", "board.jpg"};
// NOLINTNEXTLINE(readability-identifier-naming)
const char* kClasses[] = {"baboon", "fruits", "building", "board"};

cv::Mat photo(int c) {
  const std::string path = std::string(PROPRIO_OPENCV_SAMPLES) + "/" + kPhotos[c];
  cv::Mat m = cv::imread(path, cv::IMREAD_COLOR);
  EXPECT_FALSE(m.empty()) << path;
  return m;
}

class RecognitionCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    temp_.emplace("proprio_recognition_cli");
    dir_ = temp_->path();
    // 4 classes x 6 images of 96 x 96: crops of one photograph per class.
    cv::RNG rng(1);
    for (int c = 0; c < 4; ++c) {
      const cv::Mat p = photo(c);
      fs::create_directories(dir_ / "images" / kClasses[c]);
      for (int i = 0; i < 6; ++i) {
        const int s = 110 + rng.uniform(0, 60);
        const cv::Rect r(rng.uniform(0, p.cols - s), rng.uniform(0, p.rows - s), s, s);
        cv::Mat crop;
        cv::resize(p(r), crop, cv::Size(96, 96));
        cv::imwrite((dir_ / "images" / kClasses[c] / (std::to_string(i) + ".png")).string(), crop);
      }
    }
    // A vocabulary of 24 words from dense SIFT of one image per class.
    cv::Mat d;
    for (int c = 0; c < 4; ++c) {
      const cv::Mat img = cv::imread((dir_ / "images" / kClasses[c] / "0.png").string());
      d.push_back(features::dense_sift(img).descriptors);
    }
    features::KmeansOptions k;
    k.words = 24;
    features::write_vocabulary(dir_ / "v.vocab", features::build_vocabulary(d, k).vocabulary,
                               core::Provenance::current({"recognition_cli_test"}, 1));
  }
  static void TearDownTestSuite() { temp_.reset(); }
  // NOLINTNEXTLINE(readability-identifier-naming)
  static std::optional<test::TempDir> temp_;
  // NOLINTNEXTLINE(readability-identifier-naming)
  static fs::path dir_;
  std::string images() const { return (dir_ / "images").string(); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
};
std::optional<test::TempDir> RecognitionCli::temp_;
fs::path RecognitionCli::dir_;

TEST_F(RecognitionCli, DictionaryExperimentPrintsFourMatricesAndValidJson) {
  const CliRun r = run("experiment dictionary --images " + images() +
                       " --set-a baboon,fruits --set-b building,board --words 16"
                       " --dictionary-images 2 --per-image 40 --test-per-class 2 --quiet --json " +
                       file("dict.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* name : {"C_AS", "C_BS", "C_AW", "C_BW"})
    EXPECT_NE(r.out.find(name), std::string::npos) << name << "\n" << r.out;
  EXPECT_NE(r.out.find("accuracy"), std::string::npos);
  test::expect_schema_valid("experiment_sets.schema.json", file("dict.json"));
  const core::Json j = core::read_json(file("dict.json"));
  ASSERT_EQ(j["runs"].size(), 4U);
  for (const auto& run_json : j["runs"]) {
    int total = 0;
    for (const auto& row : run_json["classes"]["counts"])
      for (int n : row) total += n;
    EXPECT_EQ(total, 4);  // 2 classes x 2 test images, none without features
    EXPECT_EQ(run_json["train_documents"], 8);
  }
  EXPECT_EQ(j["set_a"], (std::vector<std::string>{"baboon", "fruits"}));
}

TEST_F(RecognitionCli, BatchOnlineExperimentRunsBothLearners) {
  const CliRun r = run("experiment batch-online --images " + images() +
                       " --words 16 --dictionary-images 2 --per-image 40 --test-per-class 2"
                       " --batch 4 --passes 3 --quiet --json " +
                       file("bo.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("C_AO"), std::string::npos);
  test::expect_schema_valid("experiment_sets.schema.json", file("bo.json"));
  const core::Json j = core::read_json(file("bo.json"));
  EXPECT_EQ(j["format"], "proprio.experiment.batch_online");
  EXPECT_EQ(j["runs"][2]["method"], "online");
  EXPECT_EQ(j["runs"][0]["method"], "batch");
}

TEST_F(RecognitionCli, TrainThenClassifyWithLabelledImages) {
  CliRun r = run("recognize train --images " + images() + " --vocabulary " + file("v.vocab") +
                 " -k 4 --passes 5 --batch 8 --model " + file("m.lda") + " --quiet --json " +
                 file("train.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  test::expect_schema_valid("recognize_train.schema.json", file("train.json"));
  r = run("recognize classify --model " + file("m.lda") + " --vocabulary " + file("v.vocab") +
          " --images " + images() + " --map-with " + images() + " --out " + file("c.csv") +
          " --quiet --json " + file("classify.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("z_4"), std::string::npos);
  test::expect_schema_valid("recognize_classify.schema.json", file("classify.json"));
  const core::Json j = core::read_json(file("classify.json"));
  EXPECT_EQ(j["documents"], 24);
  std::ifstream csv(file("c.csv"));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "image,truth,topic,class,theta_0,theta_1,theta_2,theta_3");
}

TEST_F(RecognitionCli, BadInputIsOneLineAndExitTwo) {
  fs::create_directories(dir_ / "empty");
  CliRun r = run("experiment dictionary --images " + file("empty") + " --quiet");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("empty"), std::string::npos) << r.out;

  // A class folder without images is no class; naming it is an error.
  fs::create_directories(dir_ / "images2" / "nothing");
  fs::copy(dir_ / "images", dir_ / "images2", fs::copy_options::recursive);
  r = run("experiment dictionary --images " + file("images2") +
          " --set-a nothing,baboon --set-b fruits --words 8 --test-per-class 1 --quiet");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("no class 'nothing'"), std::string::npos) << r.out;

  // An unreadable image names the file.
  std::ofstream(dir_ / "images2" / "board" / "zz.png") << "not an image";
  r = run("experiment dictionary --images " + file("images2") +
          " --words 8 --dictionary-images 1 --per-image 20 --test-per-class 1 --quiet");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("zz.png"), std::string::npos) << r.out;

  r = run("recognize train --images " + images() + " --vocabulary " + file("v.vocab") +
          " -k 0 --model " + file("k0.lda") + " --quiet");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("topics"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(file("k0.lda")));

  r = run("experiment scatter --episodes " + file("none") + " --views " + images() +
          " --k 0 --quiet");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("'0' is not a number of topics >= 1"), std::string::npos) << r.out;

  // The masks' shrinking and the grid's component caps out of range, one line naming the flag.
  for (const auto& [flags, name] : std::vector<std::pair<std::string, std::string>>{
           {" --dilate 0 --erode 101", "--erode"},
           {" --dilate 0 --erode -1", "--erode"},
           {" --erode 2", "--erode"},
           {" --mot-grid-components 1", "--mot-grid-components"},
           {" --mot-grid-components 5,1001", "--mot-grid-components"},
           {" --view-select all", "--view-select"},
           {" --mot-grid-word-weights -0.1", "--mot-grid-word-weights"},
           {" --mot-grid-word-weights 0.5,1.5", "--mot-grid-word-weights"},
           {" --dilate 0 --erode 4 --erode-min-features -1", "--erode-min-features"},
           {" --dilate 0 --erode 4 --erode-min-features 10001", "--erode-min-features"}}) {
    r = run("experiment scatter --episodes " + file("none") + " --views " + images() + flags +
            " --quiet");
    EXPECT_EQ(r.code, 2) << flags << ": " << r.out;
    EXPECT_NE(r.out.find(name), std::string::npos) << flags << ": " << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << flags << ": " << r.out;
  }

  r = run("experiment dictionary --images " + images() + " --test-per-class 6 --quiet");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("it needs more than"), std::string::npos) << r.out;
}

// A synthetic video: three textured squares (crops of three photographs) move about a grey
// table, with their ground-truth masks; views of each square alone.
TEST_F(RecognitionCli, ScatterExperimentLearnsObjectsFromAVideo) {
  const int w = 320, h = 240, frames = 40;
  const episode::EpisodeInfo info = test::synthetic_info(w, h, "recognition_cli_test", 1);
  const geometry::Camera cam = test::overhead_camera(300.0, w / 2.0, h / 2.0);
  const std::vector<episode::ObjectInfo> objects = {
      {1, "baboon", episode::ObjectRole::kTarget},
      {2, "scatter-fruits", episode::ObjectRole::kDistractor},
      {3, "scatter-building", episode::ObjectRole::kDistractor},
      {4, "scatter-board", episode::ObjectRole::kDistractor}};  // not among the views: ignored
  std::vector<cv::Mat> tex;
  for (int c = 0; c < 4; ++c) {
    cv::Mat t;
    cv::resize(photo(c)(cv::Rect(0, 0, 200, 200)), t, cv::Size(70, 70));
    tex.push_back(t);
  }
  auto write_episode = [&](const fs::path& ep, std::uint64_t seed) {
    cv::RNG rng(seed);
    test::write_synthetic_episode(ep, info, cam, objects, frames, [&](int i) {
      test::SyntheticFrame f;
      f.image = cv::Mat(h, w, CV_8UC3, cv::Scalar(140, 150, 160));
      cv::Mat1w mask(h, w, ushort{0});
      for (int c = 0; c < 4; ++c) {
        if (c > 0 && (i + 10 * c) % 25 < 5) continue;  // out of view now and then
        const cv::Rect r(rng.uniform(0, w - 70), rng.uniform(0, h - 70), 70, 70);
        tex[static_cast<std::size_t>(c)].copyTo(f.image(r));
        mask(r).setTo(c + 1);
      }
      f.arm = test::arm_at(i, info.fps, Eigen::Vector3d(0.1, 0.0, 0.0));
      f.extras.mask = mask;
      return f;
    });
  };
  write_episode(dir_ / "episodes" / "e1", 3);
  write_episode(dir_ / "held" / "h1", 4);
  write_episode(dir_ / "held" / "h2", 5);
  for (int c = 0; c < 3; ++c) {
    const fs::path vdir = dir_ / "views" / kClasses[c];
    fs::create_directories(vdir);
    for (int i = 0; i < 8; ++i) {
      cv::Mat img(160, 160, CV_8UC3, cv::Scalar(140, 150, 160));
      tex[static_cast<std::size_t>(c)].copyTo(img(cv::Rect(10 + 8 * i, 20 + 5 * i, 70, 70)));
      cv::imwrite((vdir / (std::to_string(i) + ".png")).string(), img);
    }
  }
  const CliRun r = run("experiment scatter --episodes " + (dir_ / "episodes").string() +
                       " --views " + (dir_ / "views").string() +
                       " --k objects,5 --words 24 --dictionary-frames 20 --per-frame 60 --batch 10"
                       " --passes 3 --quiet --json " +
                       file("scatter.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("K = 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("K = 5"), std::string::npos) << r.out;
  test::expect_schema_valid("experiment_scatter.schema.json", file("scatter.json"));
  const core::Json j = core::read_json(file("scatter.json"));
  EXPECT_EQ(j["frames"], frames);
  EXPECT_EQ(j["mapping_views"], 12);
  EXPECT_EQ(j["test_views"], 12);
  ASSERT_EQ(j["runs"].size(), 2U);
  // Distinct photographs on a plain table: the learned topics separate them.
  EXPECT_GE(j["runs"][0]["classes"]["mean_class_accuracy"].get<double>(), 0.6) << r.out;

  // Views cut by the masks from held-out episodes: alternate blocks of 5 frames name the topics
  // and test.
  const CliRun s = run("experiment scatter --episodes " + (dir_ / "episodes").string() +
                       " --view-episodes " + (dir_ / "held").string() +
                       " --objects baboon,fruits,building --view-step 2 --view-block 5"
                       " --k objects --words 24 --dictionary-frames 20 --per-frame 60 --batch 10"
                       " --passes 3 --quiet --json " +
                       file("scatter-held.json"));
  ASSERT_EQ(s.code, 0) << s.out;
  test::expect_schema_valid("experiment_scatter.schema.json", file("scatter-held.json"));
  const core::Json js = core::read_json(file("scatter-held.json"));
  EXPECT_EQ(js["view_step"], 2);
  // About 10 of the 20 frames used of each held-out episode, each object in view in most.
  EXPECT_GE(js["mapping_views"].get<int>(), 35);
  EXPECT_LE(js["mapping_views"].get<int>(), 60);
  EXPECT_GE(js["runs"][0]["classes"]["mean_class_accuracy"].get<double>(), 0.6) << s.out;

  // Frames classified: a model from the episode's objects, topics named by the views.
  CliRun c =
      run("recognize train --episodes " + (dir_ / "episodes").string() +
          " --region objects --objects baboon,fruits,building --vocabulary " + file("v.vocab") +
          " -k 3 --passes 5 --batch 10 --model " + file("ep.lda") + " --quiet");
  ASSERT_EQ(c.code, 0) << c.out;
  c = run("recognize classify --model " + file("ep.lda") + " --vocabulary " + file("v.vocab") +
          " --episodes " + (dir_ / "episodes" / "e1").string() +
          " --region objects --objects baboon,fruits,building --frame-step 2 --map-with " +
          (dir_ / "views").string() + " --out " + file("ep.csv") + " --quiet --json " +
          file("ep-classify.json"));
  ASSERT_EQ(c.code, 0) << c.out;
  EXPECT_NE(c.out.find("accuracy"), std::string::npos) << c.out;
  test::expect_schema_valid("recognize_classify.schema.json", file("ep-classify.json"));
  const core::Json jc = core::read_json(file("ep-classify.json"));
  EXPECT_EQ(jc["frames"], frames / 2);
  EXPECT_EQ(jc["documents"], frames / 2);
  EXPECT_EQ(jc["classes"]["rows"], (std::vector<std::string>{"baboon", "building", "fruits"}));
  std::ifstream csv(file("ep.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "episode,frame,document,truth,topic,class,theta_0,theta_1,theta_2");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, frames / 2);

  // The Mixture of Topics beside argmax theta, labelled and test views from different episodes.
  const CliRun mt =
      run("experiment scatter --episodes " + (dir_ / "episodes").string() + " --view-episodes " +
          (dir_ / "held" / "h1").string() + " " + (dir_ / "held" / "h2").string() +
          " --objects baboon,fruits,building --view-step 2 --split-by-episode --mot --dilate 3"
          " --k objects --words 24 --dictionary-frames 20 --per-frame 60 --batch 10"
          " --passes 3 --quiet --json " +
          file("scatter-mot.json"));
  ASSERT_EQ(mt.code, 0) << mt.out;
  EXPECT_NE(mt.out.find("Mixture of Topics accuracy"), std::string::npos) << mt.out;
  test::expect_schema_valid("experiment_scatter.schema.json", file("scatter-mot.json"));
  const core::Json jm = core::read_json(file("scatter-mot.json"));
  EXPECT_EQ(jm["view_split"], "episodes");
  EXPECT_EQ(jm["mask_dilate"], 3);
  EXPECT_EQ(jm["mask_erode"], 0);
  EXPECT_EQ(jm["mask_erode_min_features"], 0);
  EXPECT_EQ(jm["view_selection"], "mask");
  EXPECT_EQ(jm["test_view_origins"].size(), jm["test_views"].get<std::size_t>());
  EXPECT_EQ(jm["test_view_origins"][0]["episode"], 1);  // h2: the test episode
  EXPECT_GE(jm["runs"][0]["mot"]["mean_class_accuracy"].get<double>(), 0.6) << mt.out;
  EXPECT_GE(jm["runs"][0]["mot_unsupervised"]["mean_class_accuracy"].get<double>(), 0.45) << mt.out;
  EXPECT_GE(jm["runs"][0]["mot_unsupervised"]["chosen_classes"].get<int>(), 1);

  // proprio mot on views cut from episodes: train on one held-out episode, classify the other,
  // with an LDA model of one document per object in view (a frame of all the objects gives LDA
  // no contrast to separate them by, and theta the same for every object).
  // `recognize train` of the episodes, one document per object, with `flags`, into NAME.lda and
  // NAME.json.
  const auto train_each = [&](const std::string& flags, const std::string& name) {
    return run("recognize train --episodes " + (dir_ / "episodes").string() +
               " --region each-object --objects baboon,fruits,building --vocabulary " +
               file("v.vocab") + " -k 3 --passes 5 --batch 10 " + flags + " --model " +
               file(name + ".lda") + " --quiet --json " + file(name + ".json"));
  };
  c = train_each("", "each");
  ASSERT_EQ(c.code, 0) << c.out;
  // --colour-words (for selfsupervise --colour-words): the same documents, each feature's colour
  // word after its SIFT word: twice the tokens, and a model of the vocabulary's 24 words + 28.
  c = train_each("--colour-words --colour-weight 1", "each-c");
  ASSERT_EQ(c.code, 0) << c.out;
  test::expect_schema_valid("recognize_train.schema.json", file("each-c.json"));
  const core::Json sift_train = core::read_json(file("each.json"));
  const core::Json colour_train = core::read_json(file("each-c.json"));
  EXPECT_FALSE(sift_train["colour_words"].get<bool>());
  EXPECT_TRUE(colour_train["colour_words"].get<bool>());
  EXPECT_EQ(sift_train["words"], 24);
  EXPECT_EQ(colour_train["words"], 24 + 28);
  EXPECT_EQ(topics::load_lda_model(file("each-c.lda")).num_words(), 24 + 28);
  EXPECT_EQ(colour_train["documents"], sift_train["documents"]);
  EXPECT_EQ(colour_train["tokens"].get<long long>(), 2 * sift_train["tokens"].get<long long>());
  EXPECT_EQ(sift_train["colour_weight"], 1);  // the default 128 weighs nothing without them
  EXPECT_EQ(colour_train["colour_weight"], 1);
  // --colour-weight 4: the same documents, each colour word counted 4 times (5 times the SIFT
  // tokens), and so another model.
  c = train_each("--colour-words --colour-weight 4", "each-c4");
  ASSERT_EQ(c.code, 0) << c.out;
  test::expect_schema_valid("recognize_train.schema.json", file("each-c4.json"));
  const core::Json weighted_train = core::read_json(file("each-c4.json"));
  EXPECT_EQ(weighted_train["colour_weight"], 4);
  EXPECT_EQ(weighted_train["documents"], sift_train["documents"]);
  EXPECT_EQ(weighted_train["tokens"].get<long long>(), 5 * sift_train["tokens"].get<long long>());
  {
    const topics::LdaModel once = topics::load_lda_model(file("each-c.lda"));
    const topics::LdaModel four = topics::load_lda_model(file("each-c4.lda"));
    ASSERT_EQ(four.num_words(), 24 + 28);
    // The model records the weights, so that its readers weigh their documents alike.
    EXPECT_TRUE(once.word_weights.empty());
    EXPECT_EQ(four.word_weights, topics::weights_from(24 + 28, 24, 4));
    // The colour words hold more of the topics' mass when they count more.
    const auto colour_mass = [](const topics::LdaModel& m) {
      const Eigen::MatrixXd b = m.topic_word();
      return b.rightCols(28).sum() / b.sum();
    };
    EXPECT_GT(colour_mass(four), colour_mass(once) + 0.1);
  }
  // The default with colour words: 128 (session 47), recorded in the model.
  c = train_each("--colour-words", "each-c128");
  ASSERT_EQ(c.code, 0) << c.out;
  const core::Json default_train = core::read_json(file("each-c128.json"));
  EXPECT_EQ(default_train["colour_weight"], 128);
  EXPECT_EQ(default_train["tokens"].get<long long>(), 129 * sift_train["tokens"].get<long long>());
  EXPECT_EQ(topics::load_lda_model(file("each-c128.lda")).word_weights,
            topics::weights_from(24 + 28, 24, 128));
  c = run("recognize train --episodes " + (dir_ / "episodes").string() +
          " --region each-object --vocabulary " + file("v.vocab") + " --colour-words" +
          " --colour-weight 0 --model " + file("each-w.lda") + " --quiet");
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("colour-weight"), std::string::npos) << c.out;
  EXPECT_FALSE(fs::exists(file("each-w.lda")));
  // Images: not with colour words (one line, exit 2).
  c = run("recognize train --images " + images() + " --vocabulary " + file("v.vocab") +
          " --colour-words --model " + file("img-c.lda") + " --quiet");
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("--colour-words is for --episodes only"), std::string::npos) << c.out;
  c = run("mot train --lda-model " + file("each.lda") + " --vocabulary " + file("v.vocab") +
          " --episodes " + (dir_ / "held" / "h1").string() +
          " --objects baboon,fruits,building --view-step 2 --model " + file("ep.mot") + " --json " +
          file("ep-mot-train.json"));
  ASSERT_EQ(c.code, 0) << c.out;
  test::expect_schema_valid("mot_train.schema.json", file("ep-mot-train.json"));
  c = run("mot classify --lda-model " + file("each.lda") + " --vocabulary " + file("v.vocab") +
          " --episodes " + (dir_ / "held" / "h2").string() +
          " --objects baboon,fruits,building --view-step 2 --model " + file("ep.mot") + " --out " +
          file("ep-mot.csv") + " --json " + file("ep-mot.json"));
  ASSERT_EQ(c.code, 0) << c.out;
  test::expect_schema_valid("mot_classify.schema.json", file("ep-mot.json"));
  const core::Json jmc = core::read_json(file("ep-mot.json"));
  EXPECT_GT(jmc["documents"].get<int>(), 20);
  // Chance is 1/3; a 24-word vocabulary of other photographs' crops makes a weak model (0.55).
  EXPECT_GE(jmc["confusion"]["mean_class_accuracy"].get<double>(), 0.45) << c.out;

  // Bad input: a vocabulary of another size than the model's; an episode without its frames.
  cv::Mat d = cv::Mat(8, 128, CV_32F);
  cv::randu(d, 0.0F, 1.0F);
  features::KmeansOptions k8;
  k8.words = 4;
  features::write_vocabulary(dir_ / "v4.vocab", features::build_vocabulary(d, k8).vocabulary,
                             core::Provenance::current({"recognition_cli_test"}, 1));
  c = run("recognize classify --model " + file("ep.lda") + " --vocabulary " + file("v4.vocab") +
          " --episodes " + (dir_ / "episodes").string() + " --quiet");
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("words but the vocabulary 4"), std::string::npos) << c.out;
  fs::create_directories(dir_ / "noframes" / "h1");
  fs::copy(dir_ / "held" / "h1", dir_ / "noframes" / "h1", fs::copy_options::recursive);
  fs::remove_all(dir_ / "noframes" / "h1" / "frames");
  c = run("recognize classify --model " + file("ep.lda") + " --vocabulary " + file("v.vocab") +
          " --episodes " + (dir_ / "noframes").string() + " --quiet");
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("h1"), std::string::npos) << c.out;
  c = run("recognize classify --model " + file("ep.lda") + " --vocabulary " + file("v.vocab") +
          " --episodes " + file("images") + " --quiet");
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("holds no episode"), std::string::npos) << c.out;
  c = run("experiment scatter --episodes " + (dir_ / "episodes").string() + " --view-episodes " +
          (dir_ / "held" / "h1").string() + " --objects baboon,unicorn --quiet");
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("'unicorn' has no labelled view"), std::string::npos) << c.out;
}

}  // namespace
