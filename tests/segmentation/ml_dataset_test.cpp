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
//   PROPRIO_SEG_RIM   1: also run the Fitzpatrick & Metta baseline on each episode and print
//                     where M-L's false positives lie: inside the baseline's cut or not, and by
//                     distance to the truth's outline (a rim) and to the end-effector; with
//                     PROPRIO_SEG_DUMP a fourth panel: the baseline's mask against the truth
//   PROPRIO_SEG_CHECK_TARGETS  1: assert issue 4's targets (static >= 0.80, moving >= 0.75)
//   PROPRIO_SEG_TRACE  directory: MlDataset.TraceObjectMotion traces how the target's own pixels
//                     move against the arm over the post-touch evidence intervals (the truth's
//                     pixels carried along the flow) and where M-L's mask misses them
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "ml_test_support.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/segmentation/fm_baseline.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/segmentation/motion_models.hpp"
#include "proprio/segmentation/optical_flow.hpp"
#include "proprio/segmentation/region_tracker.hpp"

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
      cv::Mat3b fm_cmp;
      if (env("PROPRIO_SEG_RIM") == "1") {
        const FmResult fm = segment_fm(ep, FmOptions{});
        const cv::Mat1b fmask =
            fm.mask.size() == truth.size() ? fm.mask : cv::Mat1b(truth.size(), uchar{0});
        // Distance of every pixel to the truth (0 inside).
        cv::Mat1f to_truth;
        cv::distanceTransform(~truth, to_truth, cv::DIST_L2, 3);
        const auto ee = ep.ee_image(r.scored_frame);
        int fp = 0, fp_in_fm = 0, d2 = 0, d5 = 0, d10 = 0, far_ee = 0, far_ee_out_fm = 0;
        int fn = 0, fn_in_fm = 0;
        for (int y = 0; y < truth.rows; ++y)
          for (int x = 0; x < truth.cols; ++x) {
            const bool mk = r.mask(y, x) != 0, tr = truth(y, x) != 0, f = fmask(y, x) != 0;
            if (!mk && tr) {
              ++fn;
              fn_in_fm += f ? 1 : 0;
            }
            if (!mk || tr) continue;
            ++fp;
            fp_in_fm += f ? 1 : 0;
            const float d = to_truth(y, x);
            d2 += d <= 2 ? 1 : 0;
            d5 += d <= 5 ? 1 : 0;
            d10 += d <= 10 ? 1 : 0;
            const bool far = ee && std::hypot(x - ee->x(), y - ee->y()) > 40;
            far_ee += far ? 1 : 0;
            far_ee_out_fm += far && !f ? 1 : 0;
          }
        const int fhit = cv::countNonZero(fmask & truth);
        const int fn_all = cv::countNonZero(fmask);
        const int tn = cv::countNonZero(truth);
        std::printf(
            "  rim %-30s fm J %.3f P %.3f R %.3f | ML fp %d: in fm %d, <=2px %d, <=5px %d, "
            "<=10px %d, >40px from ee %d (outside fm %d) | ML fn %d: in fm %d\n",
            name.c_str(), double(fhit) / std::max(1, fn_all + tn - fhit),
            double(fhit) / std::max(1, fn_all), double(fhit) / std::max(1, tn), fp, fp_in_fm, d2,
            d5, d10, far_ee, far_ee_out_fm, fn, fn_in_fm);
        fm_cmp = cv::Mat3b(truth.size(), cv::Vec3b(0, 0, 0));
        fm_cmp.setTo(cv::Vec3b(0, 255, 0), fmask & truth);
        fm_cmp.setTo(cv::Vec3b(0, 0, 255), fmask & ~truth);
        fm_cmp.setTo(cv::Vec3b(255, 0, 0), ~fmask & truth);
      }
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
        std::vector<cv::Mat> panels{frame(roi), mapc(roi), cmp(roi)};
        if (!fm_cmp.empty()) panels.push_back(fm_cmp(roi));
        cv::hconcat(panels, row);
        cv::imwrite((fs::path(dump) / (name + ".png")).string(), row);
      }
    }
    by_group[group].add(j);
    std::string by_object = group;
    by_object += "/";
    by_object += object;
    by_group[by_object].add(j);
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

// Traces, per episode, how the target's pixels at the first touch move over the post-touch
// evidence intervals (arm moves evidence_step pixels): each truth pixel (every 2nd each way) is
// carried along the backward flow as M-L's tracks are, and its displacement u over an interval is
// compared with the arm's d: e = u - d, p = exp(-|e|^2 / (2 lambda)), the likelihood a region of
// that pixel alone would get. Also a similarity (rotation + translation) fitted to the object's
// points per interval: its angle, and the error left when the region's motion is taken as the
// arm's translation plus that rotation about the contact. Writes DIR/NAME_trace.png (touch frame;
// the pixels' mean p; M-L's mask against the truth) and prints a line per interval.
TEST(MlDataset, TraceObjectMotion) {
  const fs::path root = env("PROPRIO_CH5");
  const std::string out = env("PROPRIO_SEG_TRACE");
  if (root.empty() || out.empty()) GTEST_SKIP() << "PROPRIO_CH5 and PROPRIO_SEG_TRACE not set";
  fs::create_directories(out);
  MlOptions o;
  SparseOptions so;
  apply_overrides(env("PROPRIO_SEG_OPT"), o, so);
  for (const auto& dir : episode::list_episode_dirs(root, env("PROPRIO_SEG_FILTER"))) {
    const std::string name = dir.filename().string();
    const auto ep = episode::read_episode(dir);
    const auto t0 = ep.first_touch_frame();
    if (!t0) continue;
    const MlResult r = segment_ml(ep, o);
    const cv::Mat1b truth = ep.mask(*t0) == *ep.info().target;
    std::vector<Eigen::Vector2f> pts, start;
    for (int y = 0; y < truth.rows; y += 2)
      for (int x = 0; x < truth.cols; x += 2)
        if (truth(y, x)) pts.emplace_back(static_cast<float>(x), static_cast<float>(y));
    const std::vector<Eigen::Vector2f> at_touch = pts;
    std::vector<double> p_sum(pts.size(), 0.0);
    int intervals = 0;
    DenseFlow flow(o.flow);
    cv::Mat1b prev;
    cv::cvtColor(ep.frame(*t0), prev, cv::COLOR_BGR2GRAY);
    auto ee_a = ep.ee_image(*t0);
    start = pts;
    int frame_a = *t0;
    double sum_rot = 0, sum_fit = 0, sum_trans = 0, sum_rot_contact = 0;
    std::printf("%s touch %d  J %.3f\n", name.c_str(), *t0, testing::jaccard(r.mask, truth));
    for (int i = *t0 + 1; i < ep.frame_count() && ee_a; ++i) {
      cv::Mat1b gray;
      cv::cvtColor(ep.frame(i), gray, cv::COLOR_BGR2GRAY);
      carry_points(pts, flow.compute(gray, prev), 1.0);
      prev = gray;
      const auto ee_b = ep.ee_image(i);
      if (!ee_b || (*ee_b - *ee_a).norm() < o.evidence_step) continue;
      const Eigen::Vector2d d = *ee_b - *ee_a;
      std::vector<cv::Point2f> from, to;
      for (size_t k = 0; k < pts.size(); ++k) {
        from.emplace_back(start[k].x(), start[k].y());
        to.emplace_back(pts[k].x(), pts[k].y());
      }
      cv::Mat1b inl;
      const cv::Mat a = cv::estimateAffinePartial2D(from, to, inl, cv::RANSAC, 2.0);
      double angle = 0;
      if (!a.empty()) angle = std::atan2(a.at<double>(1, 0), a.at<double>(0, 0));
      const Eigen::Matrix2d rot =
          (Eigen::Matrix2d() << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle))
              .finished();
      double e_trans = 0, e_fit = 0, e_contact = 0, p_mean = 0;
      for (size_t k = 0; k < pts.size(); ++k) {
        const Eigen::Vector2d x0 = start[k].cast<double>(), x1 = pts[k].cast<double>();
        const Eigen::Vector2d e = x1 - x0 - d;
        const double p = motion_likelihood(e, o.lambda);
        p_sum[k] += p;
        p_mean += p;
        e_trans += e.norm();
        // The arm's translation plus the fitted rotation about the contact (ee at the start).
        const Eigen::Vector2d c = *ee_a;
        e_contact += (x1 - (c + d + rot * (x0 - c))).norm();
        if (!a.empty()) {
          const Eigen::Vector2d f(
              a.at<double>(0, 0) * x0.x() + a.at<double>(0, 1) * x0.y() + a.at<double>(0, 2),
              a.at<double>(1, 0) * x0.x() + a.at<double>(1, 1) * x0.y() + a.at<double>(1, 2));
          e_fit += (x1 - f).norm();
        }
      }
      const double n = std::max<double>(1, pts.size());
      std::printf(
          "  interval %2d frames %3d-%3d |d| %5.1f  rot %+6.2f deg  mean p %.2f  |e| trans "
          "%5.2f  similarity %5.2f  arm+rot about contact %5.2f px\n",
          intervals, frame_a, i, d.norm(), angle * 180 / std::numbers::pi, p_mean / n, e_trans / n,
          e_fit / n, e_contact / n);
      sum_rot += std::abs(angle) * 180 / std::numbers::pi;
      sum_trans += e_trans / n;
      sum_fit += e_fit / n;
      sum_rot_contact += e_contact / n;
      ++intervals;
      ee_a = ee_b;
      frame_a = i;
      start = pts;
    }
    if (intervals == 0) continue;
    std::printf(
        "  mean over %d intervals: |rot| %.2f deg, |e| trans %.2f, similarity %.2f, arm + "
        "rot about contact %.2f px\n",
        intervals, sum_rot / intervals, sum_trans / intervals, sum_fit / intervals,
        sum_rot_contact / intervals);
    // The pixels' mean p at the touch frame; M-L's recall where a pixel alone would score >= 0.5
    // and where it would not.
    cv::Mat1f pmap(truth.size(), 0.0F);
    int hi = 0, hi_hit = 0, lo = 0, lo_hit = 0;
    for (size_t k = 0; k < at_touch.size(); ++k) {
      const int x = static_cast<int>(at_touch[k].x()), y = static_cast<int>(at_touch[k].y());
      const double p = p_sum[k] / intervals;
      cv::rectangle(pmap, cv::Rect(x, y, 2, 2), cv::Scalar(p), -1);
      const bool hit = r.mask(y, x) != 0;
      (p >= 0.5 ? hi : lo) += 1;
      (p >= 0.5 ? hi_hit : lo_hit) += hit ? 1 : 0;
    }
    // Superpixels of the touch frame (fresh, as the over-segmentation cuts it) straddling the
    // outline: object pixels in superpixels that are 20-80% object.
    OverSegmenter seg(o.regions, o.region_count, o.region_iterations, truth.size());
    int count = 0;
    const cv::Mat1i sp = seg.segment(ep.frame(*t0), count);
    std::vector<int> obj(count, 0), all(count, 0);
    for (int y = 0; y < sp.rows; ++y)
      for (int x = 0; x < sp.cols; ++x) {
        ++all[sp(y, x)];
        obj[sp(y, x)] += truth(y, x) ? 1 : 0;
      }
    int straddle = 0, straddle_hit = 0, pure = 0, pure_hit = 0;
    for (int y = 0; y < sp.rows; ++y)
      for (int x = 0; x < sp.cols; ++x) {
        if (!truth(y, x)) continue;
        const double f = double(obj[sp(y, x)]) / all[sp(y, x)];
        const bool hit = r.mask(y, x) != 0;
        if (f < 0.8) {
          ++straddle;
          straddle_hit += hit ? 1 : 0;
        } else {
          ++pure;
          pure_hit += hit ? 1 : 0;
        }
      }
    std::printf(
        "  object pixels (every 2nd) alone p >= 0.5: %d, M-L recall there %.2f; p < 0.5: %d, "
        "recall %.2f | object pixels in superpixels < 80%% object: %.2f of them, recall "
        "%.2f; in the others %.2f\n",
        hi, hi ? double(hi_hit) / hi : 0.0, lo, lo ? double(lo_hit) / lo : 0.0,
        double(straddle) / std::max(1, straddle + pure),
        straddle ? double(straddle_hit) / straddle : 0.0, pure ? double(pure_hit) / pure : 0.0);
    std::fflush(stdout);
    cv::Mat frame = ep.frame(*t0).clone();
    if (const auto ee = ep.ee_image(*t0))
      cv::circle(frame, cv::Point(int(ee->x()), int(ee->y())), 4, {0, 0, 255}, -1);
    cv::Mat p8, pc;
    pmap.convertTo(p8, CV_8U, 255.0);
    cv::applyColorMap(p8, pc, cv::COLORMAP_JET);
    pc.setTo(cv::Scalar(0, 0, 0), ~truth);
    cv::Mat3b cmp(truth.size(), cv::Vec3b(0, 0, 0));
    cmp.setTo(cv::Vec3b(0, 255, 0), r.mask & truth);
    cmp.setTo(cv::Vec3b(0, 0, 255), r.mask & ~truth);
    cmp.setTo(cv::Vec3b(255, 0, 0), ~r.mask & truth);
    cv::Mat m8, mc;
    r.map.convertTo(m8, CV_8U, 255.0);
    cv::cvtColor(m8, mc, cv::COLOR_GRAY2BGR);
    cv::Rect roi = cv::boundingRect(truth);
    roi = cv::Rect(roi.x - 60, roi.y - 60, roi.width + 120, roi.height + 120) &
          cv::Rect(0, 0, truth.cols, truth.rows);
    cv::Mat row;
    cv::hconcat(std::vector<cv::Mat>{frame(roi), pc(roi), mc(roi), cmp(roi)}, row);
    cv::imwrite((fs::path(out) / (name + "_trace.png")).string(), row);
  }
}

// Heights above the table at the first touch (PROPRIO_SEG_HEIGHTS=1, a tracing aid for the depth
// variant): each pixel's depth back-projected and taken into the world (robot) frame by the
// calibration, its z in mm (the simulated table top is z = 0); per episode, the distribution of
// heights of the mask's hits, false positives and misses.
TEST(MlDataset, HeightsAtFirstTouch) {
  const fs::path root = env("PROPRIO_CH5");
  if (root.empty() || env("PROPRIO_SEG_HEIGHTS") != "1")
    GTEST_SKIP() << "PROPRIO_CH5 and PROPRIO_SEG_HEIGHTS=1 not set";
  MlOptions o;
  SparseOptions so;
  o.use_depth = true;
  apply_overrides(env("PROPRIO_SEG_OPT"), o, so);
  const std::vector<double> edges{-1e9, -5, 2, 5, 10, 20, 40, 1e9};
  for (const auto& dir : episode::list_episode_dirs(root, env("PROPRIO_SEG_FILTER"))) {
    const auto ep = episode::read_episode(dir);
    const MlResult r = segment_ml(ep, o);
    if (r.scored_frame < 0) continue;
    const cv::Mat1b truth = ep.mask(r.scored_frame) == *ep.info().target;
    cv::Mat1f z;
    ep.depth(r.scored_frame).convertTo(z, CV_32F);
    const auto& cam = ep.camera();
    const Eigen::Matrix3d k_inv = cam.K.inverse();
    std::vector<std::vector<int>> hist(3, std::vector<int>(edges.size() - 1, 0));
    for (int y = 0; y < z.rows; ++y) {
      for (int x = 0; x < z.cols; ++x) {
        const int kind = r.mask(y, x) && truth(y, x) ? 0 : r.mask(y, x) ? 1 : truth(y, x) ? 2 : -1;
        if (kind < 0 || !(z(y, x) > 0)) continue;
        const Eigen::Vector3d xc = 0.001 * z(y, x) * (k_inv * Eigen::Vector3d(x, y, 1));
        const double h = 1000.0 * (cam.R.transpose() * (xc - cam.t)).z();
        for (size_t b = 0; b + 1 < edges.size(); ++b)
          if (h >= edges[b] && h < edges[b + 1]) ++hist[static_cast<size_t>(kind)][b];
      }
    }
    std::printf("%-34s heights (mm) <-5 | -5..2 | 2..5 | 5..10 | 10..20 | 20..40 | >40\n",
                dir.filename().string().c_str());
    const char* names[] = {"hit", "false +", "missed"};
    for (size_t k = 0; k < 3; ++k) {
      std::printf("  %-8s", names[k]);
      for (const int c : hist[k]) std::printf(" %7d", c);
      std::printf("\n");
    }
  }
}

}  // namespace
}  // namespace proprio::segmentation
