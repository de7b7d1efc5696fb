#pragma once
// A small learn run directory (the layout of loop::run_learn, /docs/report.md) drawn with OpenCV
// and written with the library's own writers (vocabulary, LDA model, Mixture of Topics), for the
// report's tests: two objects, three pushes (two executed), held-out confusion matrices, timing.

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/mixture_of_topics.hpp"
#include "proprio/topics/mot_model_io.hpp"

namespace proprio::test {

struct LearnRunFixture {
  /// A truth name with HTML in it: the page must show it escaped.
  std::string hostile_truth = "<b>bottle</b> & \"cap\"";
  int width = 320;
  int height = 240;
  bool models = true;  ///< write vocabulary.vocab, lda.model, model.mot
  bool table = true;   ///< write table.png
};

namespace learn_fixture_detail {

inline void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  std::filesystem::create_directories(path.parent_path());
  if (!cv::imwrite(path.string(), image)) throw std::runtime_error("cannot write " + path.string());
}

// The table with a red box (object_1) at `a` and a blue disc (object_2) at `b`.
inline cv::Mat draw_table(const LearnRunFixture& f, cv::Point a, cv::Point b) {
  cv::Mat img(f.height, f.width, CV_8UC3, cv::Scalar(120, 150, 170));
  cv::rectangle(img, a - cv::Point(20, 14), a + cv::Point(20, 14), cv::Scalar(40, 40, 200), -1);
  cv::circle(img, b, 16, cv::Scalar(200, 80, 40), -1);
  return img;
}

}  // namespace learn_fixture_detail

/// Writes the run directory `dir` (created; files in it replaced).
inline void write_learn_run_fixture(const std::filesystem::path& dir,
                                    const LearnRunFixture& f = {}) {
  namespace fs = std::filesystem;
  using core::Json;
  using learn_fixture_detail::draw_table;
  using learn_fixture_detail::write_png;
  fs::create_directories(dir);
  const cv::Point a0(100, 120);
  const cv::Point b0(220, 110);
  if (f.table) write_png(dir / "table.png", draw_table(f, a0, b0));

  // Push 0 moves object_1 right, push 1 moves object_2 down, push 2 was not executed.
  const cv::Point moves[2] = {{30, 0}, {0, 40}};
  Json pushes = Json::array();
  for (int i = 0; i < 3; ++i) {
    const std::string sub = "pushes/push_00" + std::to_string(i);
    const bool executed = i < 2;
    const cv::Point start = i == 0 ? a0 - cv::Point(35, 0) : b0 - cv::Point(0, 30);
    const cv::Point end = i == 0 ? a0 + moves[0] : b0 + moves[1];
    Json push = {{"index", i},
                 {"class", i == 1 ? "object_2" : "object_1"},
                 {"dir", sub},
                 {"plan",
                  {{"start_px", {start.x, start.y}},
                   {"end_px", {end.x, end.y}},
                   {"start", {0.25 + 0.01 * i, -0.05}},
                   {"end", {0.31, -0.05}},
                   {"cost", 1.5 + i}}},
                 {"executed", executed},
                 {"frames", executed ? 40 : 0},
                 {"views", executed ? 6 : 0},
                 {"moved_intended", executed},
                 {"outcome", executed ? "pushed" : "robot-refused"}};
    pushes.push_back(push);
    if (!executed) continue;
    const cv::Point a1 = i == 0 ? a0 + moves[0] : a0;
    const cv::Point b1 = i == 1 ? b0 + moves[1] : b0;
    const cv::Point centre = i == 0 ? a1 : b1;
    const fs::path d = dir / sub;
    write_png(d / "before.png", draw_table(f, a0, b0));
    const cv::Mat after = draw_table(f, a1, b1);
    write_png(d / "after.png", after);
    write_png(d / "frame.png", after);
    cv::Mat map(f.height, f.width, CV_8U);
    for (int y = 0; y < f.height; ++y) {
      for (int x = 0; x < f.width; ++x) {
        const double r2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
        map.at<uchar>(y, x) = cv::saturate_cast<uchar>(255.0 * std::exp(-r2 / (2 * 18.0 * 18.0)));
      }
    }
    write_png(d / "map.png", map);
    cv::Mat mask = map > 128;
    write_png(d / "mask.png", mask);
  }
  write_png(dir / "words" / "object_1.png",
            draw_table(f, a0, b0)(cv::Rect(60, 90, 80, 60)).clone());

  Json conf_mot = {{"accuracy", 0.85},
                   {"rows", {"box", f.hostile_truth}},
                   {"columns", {"object_1", "object_2"}},
                   {"counts", {{18, 2}, {4, 16}}}};
  Json conf_argmax = {{"accuracy", 0.6},
                      {"rows", {"box", f.hostile_truth}},
                      {"columns", {"object_1", "object_2"}},
                      {"counts", {{12, 8}, {8, 12}}}};
  const Json doc = {
      {"format", "proprio.learn"},
      {"format_version", 1},
      {"complete", true},
      {"options", {{"objects", "box,bottle"}, {"seed", 1}, {"pushes", 3}, {"topics", 3}}},
      {"objects",
       {{{"class", "object_1"}, {"truth", "box"}, {"pushes", 2}, {"views", 12}, {"purity", 0.9}},
        {{"class", "object_2"},
         {"truth", f.hostile_truth},
         {"pushes", 1},
         {"views", 6},
         {"purity", 1.0}}}},
      {"pushes", pushes},
      {"held_out", {{"views_per_object", 20}, {"mot", conf_mot}, {"argmax", conf_argmax}}},
      {"timing",
       {{{"stage", "look"}, {"seconds", 0.5}, {"clock", "wall"}},
        {{"stage", "push"}, {"seconds", 6.0}, {"clock", "wall"}},
        {{"stage", "segmentation"}, {"seconds", 2.25}, {"clock", "wall"}},
        {{"stage", "held_out"}, {"seconds", 1.0}, {"clock", "wall"}}}},
      {"vocabulary", {{"words", 12}, {"file", "vocabulary.vocab"}}},
      {"topics", {{"count", 3}, {"file", "lda.model"}}},
      {"model", "model.mot"}};
  core::write_json_atomic(dir / "learn.json", doc);
  core::write_file_atomic(dir / "decisions.jsonl",
                          "{\"event\":\"start\",\"objects\":2}\n"
                          "{\"event\":\"look\",\"round\":0,\"note\":\"<i>x</i>\"}\n"
                          "{\"event\":\"push\",\"round\":0}\n"
                          "{\"event\":\"push\",\"round\":1}\n"
                          "{\"event\":\"end\"}\n");
  if (!f.models) return;

  const int words = 12;
  const int topics_k = 3;
  cv::Mat centres(words, 128, CV_32F);
  for (int w = 0; w < words; ++w) {
    for (int d = 0; d < 128; ++d) centres.at<float>(w, d) = static_cast<float>((w * 7 + d) % 13);
  }
  features::write_vocabulary(dir / "vocabulary.vocab", features::Vocabulary(centres),
                             core::Provenance{});
  topics::LdaModel lda;
  lda.lambda = Eigen::MatrixXd::Constant(topics_k, words, 0.5);
  for (int w = 0; w < words; ++w) lda.lambda(w % topics_k, w) += 10.0 + w;
  lda.alpha = 1.0 / topics_k;
  lda.eta = 0.1;
  topics::save_lda_model(lda, dir / "lda.model");
  core::Rng rng(3);
  Eigen::VectorXd a1(3);
  a1 << 8.0, 1.0, 0.5;
  Eigen::VectorXd a2(3);
  a2 << 0.5, 2.0, 6.0;
  Eigen::MatrixXd theta(40, 3);
  std::vector<int> labels;
  for (int i = 0; i < 40; ++i) {
    theta.row(i) = topics::Dirichlet(i < 20 ? a1 : a2).sample(rng).transpose();
    labels.push_back(i < 20 ? 0 : 1);
  }
  const topics::MotModel mot = topics::fit_mot(theta, labels, {"object_1", "object_2"}).model;
  topics::save_mot_model(mot, topics::mot_basis(lda), dir / "model.mot");
}

}  // namespace proprio::test
