// Scoring M-L over a dataset of episodes (the simulator's thesis-ch5 set): mean Jaccard at the
// first-touch frame by object and background (thesis 5.1.1). Slow (minutes): a tuning tool that
// ctest does not run (tests/segmentation/CMakeLists.txt).
//
// Environment:
//   PROPRIO_CH5       dataset directory (required; the tool skips when it is unset)
//   PROPRIO_SEG_FILTER  only episodes whose name contains this (episode::list_episode_dirs)
//   PROPRIO_SEG_OPT   option overrides "key=value,key=value" by the names of MlOptions's and
//                     SparseOptions's descriptions (model=homography, flow=dis-ultrafast,
//                     regions=slic, lambda=10, contact_prior=false, ...)
//   PROPRIO_SEG_SPARSE  1: score segment_ml_sparse instead
//   PROPRIO_SEG_DUMP  directory for PNGs (frame, map, mask vs truth) per episode
//   PROPRIO_SEG_CSV   per-episode CSV output
//   PROPRIO_SEG_CHECK_TARGETS  1: assert issue 4's targets (static >= 0.80, moving >= 0.75)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "ml_test_support.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::segmentation {
namespace {

namespace fs = std::filesystem;

std::string env(const char* name, const std::string& fallback = "") {
  const char* v = std::getenv(name);
  return v ? std::string(v) : fallback;
}

// A "key=value" override as JSON: true/false, a number, or text (a choice's name).
core::Json value_of(const std::string& text) {
  if (text == "true" || text == "false") return text == "true";
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (!text.empty() && end == text.c_str() + text.size()) {
    if (x == static_cast<double>(static_cast<long long>(x)) && text.find('.') == std::string::npos)
      return static_cast<long long>(x);
    return x;
  }
  return text;
}

// PROPRIO_SEG_OPT into the options, by the names of MlOptions's and SparseOptions's one
// description (a name both have sets both); an unknown name or a bad value is an Error.
void apply_overrides(const std::string& text, MlOptions& ml, SparseOptions& sparse) {
  core::Json for_ml = core::Json::object();
  core::Json for_sparse = core::Json::object();
  const auto ml_names = core::field_names<MlOptions>();
  const auto sparse_names = core::field_names<SparseOptions>();
  std::stringstream opts(text);
  for (std::string kv; std::getline(opts, kv, ',');) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw Error("PROPRIO_SEG_OPT: '" + kv + "' is not key=value");
    const std::string key = kv.substr(0, eq);
    const core::Json value = value_of(kv.substr(eq + 1));
    const bool in_ml = std::find(ml_names.begin(), ml_names.end(), key) != ml_names.end();
    const bool in_sparse =
        std::find(sparse_names.begin(), sparse_names.end(), key) != sparse_names.end();
    if (in_ml) for_ml[key] = value;
    if (in_sparse) for_sparse[key] = value;
    if (!in_ml && !in_sparse) for_ml[key] = value;  // reported as unknown, with the known names
  }
  core::fields_from_json(for_ml, ml, "PROPRIO_SEG_OPT");
  core::fields_from_json(for_sparse, sparse, "PROPRIO_SEG_OPT");
}

TEST(MlDatasetTool, OverridesUseTheOptionsDescriptions) {
  MlOptions ml;
  SparseOptions sparse;
  apply_overrides("model=homography,lambda=10,region_count=300,contact_prior=false,tau=0.25", ml,
                  sparse);
  EXPECT_EQ(ml.model, MotionModel::kHomography);
  EXPECT_EQ(ml.lambda, 10.0);
  EXPECT_EQ(sparse.lambda, 10.0);  // both describe lambda
  EXPECT_EQ(ml.region_count, 300);
  EXPECT_FALSE(ml.contact_prior);
  EXPECT_EQ(sparse.tau, 0.25);
  EXPECT_THROW(apply_overrides("colour=1", ml, sparse), Error);
  EXPECT_THROW(apply_overrides("flow=optical", ml, sparse), Error);
  EXPECT_THROW(apply_overrides("region_count=3.5", ml, sparse), Error);
}

struct Score {
  double sum = 0;
  int n = 0;
  void add(double j) {
    sum += j;
    ++n;
  }
  [[nodiscard]] double mean() const { return n ? sum / n : 0.0; }
};

TEST(MlDataset, JaccardAtFirstTouch) {
  const fs::path root = env("PROPRIO_CH5");
  if (root.empty()) GTEST_SKIP() << "PROPRIO_CH5 (a dataset directory) is not set";
  MlOptions o;
  SparseOptions so;
  apply_overrides(env("PROPRIO_SEG_OPT"), o, so);
  const bool sparse = env("PROPRIO_SEG_SPARSE") == "1";
  const std::string filter = env("PROPRIO_SEG_FILTER");
  const std::string dump = env("PROPRIO_SEG_DUMP");
  const std::vector<fs::path> dirs = episode::list_episode_dirs(root, filter);
  std::map<std::string, Score> by_group;
  std::ofstream csv;
  if (!env("PROPRIO_SEG_CSV").empty()) {
    csv.open(env("PROPRIO_SEG_CSV"));
    csv << "episode,group,object,first_touch,jaccard,precision,recall,ms_total\n";
  }
  double ms = 0;
  int timed = 0;
  for (const auto& dir : dirs) {
    const std::string name = dir.filename().string();
    const auto ep = episode::read_episode(dir);
    const MlResult r = sparse ? segment_ml_sparse(ep, so) : segment_ml(ep, o);
    // Names: push_<object>_<static|moving>_<k> or homography_<...>.
    std::string group = "other", object = "?";
    std::vector<std::string> parts;
    std::stringstream ss(name);
    for (std::string p; std::getline(ss, p, '_');) parts.push_back(p);
    if (parts.size() >= 4 && parts[0] == "push") {
      object = parts[1];
      for (size_t k = 2; k + 2 < parts.size(); ++k) object += "_" + parts[k];
      group = parts[parts.size() - 2];
    } else if (!parts.empty()) {
      group = parts[0];
      object = parts.size() > 1 ? parts[1] : "?";
    }
    double j = 0, prec = 0, rec = 0;
    if (r.scored_frame >= 0) {
      const cv::Mat1b truth = ep.mask(r.scored_frame) == *ep.info().target;
      j = testing::jaccard(r.mask, truth);
      const int hit = cv::countNonZero(r.mask & truth);
      prec = cv::countNonZero(r.mask) ? double(hit) / cv::countNonZero(r.mask) : 0;
      rec = cv::countNonZero(truth) ? double(hit) / cv::countNonZero(truth) : 0;
      if (!dump.empty()) {
        fs::create_directories(dump);
        cv::Mat frame = ep.frame(r.scored_frame);
        cv::Mat map8, mapc;
        r.map.convertTo(map8, CV_8U, 255.0);
        cv::cvtColor(map8, mapc, cv::COLOR_GRAY2BGR);
        cv::Mat3b cmp(truth.size(), cv::Vec3b(0, 0, 0));  // green hit, red false +, blue missed
        cmp.setTo(cv::Vec3b(0, 255, 0), r.mask & truth);
        cmp.setTo(cv::Vec3b(0, 0, 255), r.mask & ~truth);
        cmp.setTo(cv::Vec3b(255, 0, 0), ~r.mask & truth);
        if (const auto ee = ep.ee_image(r.scored_frame))
          cv::circle(frame, cv::Point(int(ee->x()), int(ee->y())), 4, {0, 0, 255}, -1);
        // Full resolution around the object: 100 pixels beyond the truth's bounding box.
        cv::Rect roi = cv::boundingRect(truth);
        roi = cv::Rect(roi.x - 100, roi.y - 100, roi.width + 200, roi.height + 200) &
              cv::Rect(0, 0, truth.cols, truth.rows);
        if (roi.area() == 0) roi = cv::Rect(0, 0, truth.cols, truth.rows);
        cv::Mat row;
        cv::hconcat(std::vector<cv::Mat>{frame(roi), mapc(roi), cmp(roi)}, row);
        cv::imwrite((fs::path(dump) / (name + ".png")).string(), row);
      }
    }
    by_group[group].add(j);
    by_group[group + "/" + object].add(j);
    by_group["all"].add(j);
    ms += r.summary.mean_ms_total;
    ++timed;
    std::printf("%-34s touch %4d  J %.3f  P %.3f  R %.3f  %.1f ms/frame  camera %.2f px (%d/%d)\n",
                name.c_str(), r.scored_frame, j, prec, rec, r.summary.mean_ms_total,
                r.summary.mean_camera_motion, r.summary.camera_fits,
                r.summary.camera_fits + r.summary.camera_failures);
    std::fflush(stdout);
    if (csv.is_open())
      csv << name << ',' << group << ',' << object << ',' << r.scored_frame << ',' << j << ','
          << prec << ',' << rec << ',' << r.summary.mean_ms_total << '\n';
  }
  std::printf("\nmean Jaccard by group (episodes):\n");
  for (const auto& [g, s] : by_group) std::printf("  %-28s %.3f (%d)\n", g.c_str(), s.mean(), s.n);
  if (timed) std::printf("mean time %.1f ms/frame\n", ms / timed);
  if (env("PROPRIO_SEG_CHECK_TARGETS") == "1") {
    EXPECT_GE(by_group["static"].mean(), 0.80);
    EXPECT_GE(by_group["moving"].mean(), 0.75);
  }
}

}  // namespace
}  // namespace proprio::segmentation
