// `proprio learn`: look, plan, move (thesis Ch 8). See the header.
#include "proprio/loop/learn.hpp"
#include "proprio/geometry/depth_pixels.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <numeric>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string_view>

#include "arm_image.hpp"
#include "blob_tracking.hpp"
#include "proprio/core/cpu_clock.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/mask_morphology.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/loop/learn_report.hpp"
#include "proprio/loop/self_supervision.hpp"
#include "proprio/loop/self_supervision_scoring.hpp"
#include "proprio/loop/view_model.hpp"
#include "proprio/recognition/confusion.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/mot_model_io.hpp"

namespace proprio::loop {

namespace fs = std::filesystem;

namespace {

constexpr int kFormatVersion = 1;
constexpr std::uint64_t kChoiceStream = 0x63686f696365ULL;  // core::stream_seed key: choices
constexpr std::uint64_t kPlanStream = 0x706c616eULL;        // core::stream_seed key: push plans
constexpr std::size_t kMaxObjects = 8;  // the most objects a simulated table holds
constexpr double kTrackRadius = 0.08;   // a blob is the object when its centre is this near, m
constexpr double kLandRadius = 0.15;    // a pushed object is looked for this near its target, m
constexpr double kHoldRadius = 0.05;  // hold_target: the object is the blob this near its target, m
constexpr double kStill = 0.01;       // moved less than this: did not move, m
constexpr double kPushStep = 0.06;    // an object is pushed this far a push, m
constexpr int kDirections = 12;       // directions a push target is chosen from
constexpr double kCrowded = 0.15;     // blobs further than this from a target do not matter, m
// Push targets stay where the arm can push them again and the camera sees them (robot base
// frame, m): within kTargetReach of the base axis (a push from behind needs room past the
// object), beyond kTargetNear (clear of the arm's base), within kTargetSide of the view's centre
// line. Inside that area a target is not pulled anywhere: pulling every object toward the
// view's centre pushed them all into one clump.
constexpr double kTargetReach = 0.36;
constexpr double kTargetNear = 0.16;
constexpr double kTargetSide = 0.27;
// ... and in front of the base (x at least this, m): an object pushed beside or behind the base
// stands where every transit (raised over the base, turned toward the start) passes; on seed 1
// pushes to x 0.085-0.1 were followed by refused transits.
constexpr double kTargetFront = 0.12;
// keep_in_reach: what a push target outside that area costs in push_target's score (more than
// any gap, kCrowded), m.
constexpr double kOutsideArea = 1.0;
constexpr int kSides = 8;                           // sides tried when a push is out of reach
constexpr double kSidePush = 0.08;                  // how far those pushes go, m
constexpr double kGoldenAngle = 2.399963229728653;  // rad
constexpr double kApproachStep = 0.03;              // approach added after a refusal, m
// The arm's pushing reach (robot base frame): a blob whose table centre is further from the
// base axis than this, or behind the base, cannot be pushed from behind; it is not an object
// to learn (distractors moving behind the work area, the backdrop), m.
constexpr double kPushReach = 0.44;
constexpr double kBehindBase = 0.0;  // least x of a blob's centre, m
// start_clearance: a push start is not clear when the hand would meet this many depth points
// (a stray pixel or two at an object's rim is no object).
constexpr int kHandLeastPoints = 3;
// candidate_footprint: every this many px of a candidate are back-projected (as the planner's).
constexpr int kFootprintStep = 2;
constexpr int kMaxFailures = 3;  // pushes in a row not planned or refused: move on
constexpr int kMaxMerges =
    2;  // identity_margin: a turn's pushes merged into known objects, at most
constexpr double kMaxExtraApproach = 0.12;  // at most, m
constexpr int kMaxMatchPool = 4000;         // "match": a known object's descriptors, at most
// carry_regions: a region is the object's where this fraction of its features match its views
// (new objects' blobs matched 0.00-0.05 in 7 of 11 choices, known ones 0.14 or more in 12 of 14).
constexpr double kCarryMatched = 0.1;
// LearnCandidates::kDepth: a candidate covers at least this many px of a 640-wide image (scaled
// with the image's area; the cd covers about 600 px of a 320 x 240 look).
constexpr double kCandidatePixels = 150;

using Clock = std::chrono::steady_clock;

void write_png(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> buf;
  if (!cv::imencode(".png", image, buf)) throw Error(path.string() + ": cannot encode the image");
  core::write_file_atomic(path,
                          std::string_view(reinterpret_cast<const char*>(buf.data()), buf.size()));
}

using detail::blob_mask;

int track(const planning::PlanningView& view, const Eigen::Vector2d& centre, double radius) {
  return detail::nearest_blob(view, centre, radius);
}

// The blob of `view` with most feature points inside `mask` (image size); -1 none.
int blob_on(const planning::PlanningView& view, const cv::Mat1b& mask) {
  int best = -1;
  int best_n = 0;
  for (std::size_t b = 0; b < view.objects.size(); ++b) {
    int n = 0;
    for (const auto& p : view.objects[b].pixels) {
      const int u = std::clamp(static_cast<int>(std::lround(p.x())), 0, mask.cols - 1);
      const int v = std::clamp(static_cast<int>(std::lround(p.y())), 0, mask.rows - 1);
      if (mask(v, u) != 0) ++n;
    }
    if (n > best_n) {
      best_n = n;
      best = static_cast<int>(b);
    }
  }
  return best;
}

// Rows of `x` as a CV_32F matrix.
cv::Mat float_rows(const Eigen::MatrixXd& x) {
  cv::Mat m;
  if (x.rows() == 0) return m;
  cv::eigen2cv(x, m);
  m.convertTo(m, CV_32F);
  return m;
}

// Nearest-neighbour distances of each row of `query` among the rows of `pool`.
std::vector<float> nearest_distances(const cv::Mat& query, const cv::Mat& pool) {
  std::vector<cv::DMatch> matches;
  cv::BFMatcher(cv::NORM_L2).match(query, pool, matches);
  std::vector<float> d(static_cast<std::size_t>(query.rows), std::numeric_limits<float>::max());
  for (const auto& m : matches) d[static_cast<std::size_t>(m.queryIdx)] = m.distance;
  return d;
}

// A look's features: positions and unit descriptors.
struct LookFeatures {
  std::vector<cv::Point2f> points;
  Eigen::MatrixXd unit;
};

// One segmented view: its raw descriptors (for the vocabulary) and its class.
struct View {
  int cls = 0;
  int push = 0;
  cv::Mat descriptors;
  std::vector<std::int32_t> colours;  ///< LearnOptions::colour_words: one a descriptor
};

// passes: a later pass's turn, its object found in `view` (blob, how it was located).
struct Revisit {
  planning::PlanningView view;
  int blob = -1;
  std::string how;
  int pass = 2;
};

// Where a turn's last executed push left its object: locate()'s first cue at the turn's next
// push.
enum class Landing {
  kUnknown,   // no push of the turn yet (or it was merged into a known object), or no cue on
  kHeld,      // hold_target: a blob lay within kHoldRadius of the push's target
  kNear,      // region_agree: its blob lay within region_agree of the push's target
  kNearHeld,  // both (hold_target and region_agree on)
  kLost       // region_agree: no blob lay within region_agree of the target (the turn ends)
};

bool is_near(Landing l) { return l == Landing::kNear || l == Landing::kNearHeld; }
bool is_held(Landing l) { return l == Landing::kHeld || l == Landing::kNearHeld; }

std::vector<std::string> names_or_empty(const std::string& list) {
  const auto l = list.find_first_not_of(" \t");
  if (l == std::string::npos) return {};
  return parse_object_list(list);
}

}  // namespace

double descriptor_match_fraction(const cv::Mat& query, const cv::Mat& known, const cv::Mat& rest,
                                 double ratio) {
  if (!(ratio > 0 && ratio <= 1)) throw Error("descriptor match: ratio must be in (0, 1]");
  for (const cv::Mat* m : {&query, &known, &rest}) {
    if (!m->empty() && m->type() != CV_32F) throw Error("descriptor match: descriptors not CV_32F");
    if (!m->empty() && !query.empty() && m->cols != query.cols) {
      throw Error("descriptor match: descriptors of different lengths");
    }
  }
  if (query.empty() || known.empty()) return 0.0;
  const std::vector<float> dk = nearest_distances(query, known);
  std::vector<float> dr(dk.size(), std::numeric_limits<float>::max());
  if (!rest.empty()) dr = nearest_distances(query, rest);
  int matched = 0;
  for (std::size_t i = 0; i < dk.size(); ++i) {
    if (dk[i] < std::numeric_limits<float>::max() &&
        (dr[i] == std::numeric_limits<float>::max() || dk[i] < ratio * dr[i])) {
      ++matched;
    }
  }
  return static_cast<double>(matched) / static_cast<double>(query.rows);
}

RegionFate carry_region(const cv::Mat& region, const cv::Point2d& shift,
                        const std::vector<cv::Point2f>& points, const cv::Mat& descriptors,
                        const cv::Mat& pool, double ratio, double min_matched, cv::Mat& out) {
  if (region.empty() || region.type() != CV_8U) throw Error("carry region: not an 8-bit mask");
  if (static_cast<int>(points.size()) != descriptors.rows) {
    throw Error("carry region: points and descriptors differ in number");
  }
  out = cv::Mat();
  const cv::Mat moved_by = (cv::Mat_<double>(2, 3) << 1, 0, shift.x, 0, 1, shift.y);
  cv::Mat carried;
  cv::warpAffine(region, carried, moved_by, region.size(), cv::INTER_NEAREST);
  const cv::Rect image(0, 0, region.cols, region.rows);
  const auto score = [&](const cv::Mat& r) {
    cv::Mat in(0, descriptors.cols, CV_32F);
    cv::Mat rest(0, descriptors.cols, CV_32F);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const cv::Point p(static_cast<int>(points[i].x), static_cast<int>(points[i].y));
      const bool inside = image.contains(p) && r.at<uchar>(p) != 0;
      (inside ? in : rest).push_back(descriptors.row(static_cast<int>(i)));
    }
    return descriptor_match_fraction(in, pool, rest, ratio);
  };
  const double stayed = score(region);
  const double moved = cv::countNonZero(carried) > 0 ? score(carried) : 0.0;
  if (std::max(stayed, moved) < min_matched) return RegionFate::kLost;
  if (moved > stayed) {
    out = carried;
    return RegionFate::kCarried;
  }
  out = region.clone();
  return RegionFate::kStayed;
}

LearnOptions LearnOptions::resolved() const {
  LearnOptions o = *this;
  if (o.candidates == LearnCandidates::kDepth) o.depth = true;  // candidates need the depth image
  if (o.headline == LearnHeadline::kAuto) {
    o.headline = o.colour_words ? LearnHeadline::kColour : LearnHeadline::kPooled;
  }
  if (!quick) return o;
  const LearnOptions d;
  if (o.pushes == d.pushes) o.pushes = o.quick_pushes;
  if (o.width == d.width && o.height == d.height) {
    o.width = 240;
    o.height = 180;
  }
  if (o.words == d.words) o.words = 100;
  if (o.topics == d.topics) o.topics = 6;
  return o;
}

std::vector<cv::Mat> depth_candidates(const cv::Mat& depth, const geometry::Camera& camera,
                                      double min_height, double max_step, int min_pixels,
                                      const cv::Mat& ignore) {
  require(depth.type() == CV_32FC1 && depth.cols == camera.width && depth.rows == camera.height,
          "depth_candidates: the depth image must be CV_32FC1 of the camera's image size");
  require(ignore.empty() || (ignore.type() == CV_8U && ignore.size() == depth.size()),
          "depth_candidates: the ignore mask must be 8-bit of the depth image's size");
  require(min_height > 0 && std::isfinite(min_height), "depth_candidates: min_height must be > 0");
  require(max_step > 0 && std::isfinite(max_step), "depth_candidates: max_step must be > 0");
  require(min_pixels >= 1, "depth_candidates: min_pixels must be at least 1");
  const geometry::DepthPixels pixels(camera);
  const auto valid = [&](int u, int v) {
    const float d = depth.at<float>(v, u);
    return geometry::depth_measured(d) && (ignore.empty() || ignore.at<uchar>(v, u) == 0);
  };
  cv::Mat1b up(depth.size(), 0);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      if (!valid(u, v)) continue;
      const double d = depth.at<float>(v, u);
      const Eigen::Vector3d x = pixels.world(u, v, d);
      if (x.z() < min_height) continue;
      // An occlusion edge: a 4-neighbour's depth differs by more than max_step.
      bool edge = false;
      const int du[4] = {1, -1, 0, 0};
      const int dv[4] = {0, 0, 1, -1};
      for (int n = 0; n < 4 && !edge; ++n) {
        const int uu = u + du[n];
        const int vv = v + dv[n];
        if (uu < 0 || vv < 0 || uu >= depth.cols || vv >= depth.rows || !valid(uu, vv)) continue;
        edge = std::abs(static_cast<double>(depth.at<float>(vv, uu)) - d) > max_step;
      }
      if (!edge) up(v, u) = 255;
    }
  }
  cv::Mat1i labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int n = cv::connectedComponentsWithStats(up, labels, stats, centroids, 8, CV_32S);
  std::vector<std::pair<int, int>> order;  // (area, label)
  for (int l = 1; l < n; ++l) {
    const int area = stats.at<int>(l, cv::CC_STAT_AREA);
    if (area >= min_pixels) order.emplace_back(area, l);
  }
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::vector<cv::Mat> out;
  for (const auto& [area, l] : order) {
    cv::Mat m = labels == l;
    out.push_back(m);
  }
  return out;
}

std::vector<int> known_candidates(const std::vector<cv::Mat>& regions,
                                  const std::vector<cv::Mat>& candidates,
                                  const std::vector<std::optional<cv::Point2d>>& ends) {
  cv::Size size;
  const auto check = [&](const cv::Mat& m) {
    if (m.empty()) return;
    require(m.type() == CV_8U, "known_candidates: the masks must be 8-bit");
    if (size.area() == 0) size = m.size();
    require(m.size() == size, "known_candidates: the masks must have one size");
  };
  for (const cv::Mat& m : regions) check(m);
  for (const cv::Mat& m : candidates) check(m);
  require(ends.empty() || ends.size() == regions.size(),
          "known_candidates: one push end per region (or none)");
  struct Overlap {
    int tenths;       // the fraction of the candidate inside the region, to a tenth
    double distance;  // of the candidate's centroid from the push's end, px (0 without one)
    int pixels;
    int region;
    int candidate;
  };
  std::vector<Overlap> all;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (regions[r].empty()) continue;
    for (std::size_t b = 0; b < candidates.size(); ++b) {
      if (candidates[b].empty()) continue;
      cv::Mat both;
      cv::bitwise_and(regions[r], candidates[b], both);
      const int n = cv::countNonZero(both);
      if (n == 0) continue;
      const cv::Moments m = cv::moments(candidates[b], true);
      double distance = 0;
      if (!ends.empty() && ends[r]) {
        distance = std::hypot(m.m10 / m.m00 - ends[r]->x, m.m01 / m.m00 - ends[r]->y);
      }
      const int tenths = static_cast<int>(std::lround(10.0 * n / m.m00));
      all.push_back({tenths, distance, n, static_cast<int>(r), static_cast<int>(b)});
    }
  }
  std::sort(all.begin(), all.end(), [](const Overlap& a, const Overlap& b) {
    if (a.tenths != b.tenths) return a.tenths > b.tenths;
    if (a.distance != b.distance) return a.distance < b.distance;
    if (a.pixels != b.pixels) return a.pixels > b.pixels;
    return a.region != b.region ? a.region < b.region : a.candidate < b.candidate;
  });
  std::vector<int> found(regions.size(), -1);
  std::vector<bool> taken(candidates.size(), false);
  for (const Overlap& o : all) {
    auto& f = found[static_cast<std::size_t>(o.region)];
    if (f >= 0 || taken[static_cast<std::size_t>(o.candidate)]) continue;
    f = o.candidate;
    taken[static_cast<std::size_t>(o.candidate)] = true;
  }
  return found;
}

std::vector<Eigen::Vector3d> depth_points(const cv::Mat& depth, const geometry::Camera& camera,
                                          double min_height, int step, const cv::Mat& ignore) {
  require(depth.type() == CV_32FC1 && depth.cols == camera.width && depth.rows == camera.height,
          "depth_points: the depth image must be CV_32FC1 of the camera's image size");
  require(ignore.empty() || (ignore.type() == CV_8U && ignore.size() == depth.size()),
          "depth_points: the ignore mask must be 8-bit of the depth image's size");
  require(min_height >= 0 && std::isfinite(min_height), "depth_points: min_height must be >= 0");
  require(step >= 1, "depth_points: step must be at least 1");
  const geometry::DepthPixels pixels(camera);
  std::vector<Eigen::Vector3d> out;
  for (int v = 0; v < depth.rows; v += step) {
    for (int u = 0; u < depth.cols; u += step) {
      const float d = depth.at<float>(v, u);
      if (!geometry::depth_measured(d) || (!ignore.empty() && ignore.at<uchar>(v, u) != 0)) {
        continue;
      }
      const Eigen::Vector3d x = pixels.world(u, v, d);
      if (x.z() >= min_height) out.push_back(x);
    }
  }
  return out;
}

int hand_meets(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector2d& start,
               const HandClearance& clearance) {
  for (const double q :
       {clearance.pusher, clearance.pusher_height, clearance.hand, clearance.hand_height}) {
    require(q >= 0 && std::isfinite(q),
            "hand_meets: the clearance's distances and heights must be >= 0 and finite");
  }
  int met = 0;
  for (const Eigen::Vector3d& p : points) {
    const double r = (p.head<2>() - start).norm();
    if ((r < clearance.pusher && p.z() > clearance.pusher_height) ||
        (r < clearance.hand && p.z() > clearance.hand_height)) {
      ++met;
    }
  }
  return met;
}

std::vector<double> moved_fractions(const cv::Mat& before, const cv::Mat& after,
                                    const std::vector<cv::Mat>& masks, double change) {
  require(before.type() == CV_32FC1 && after.type() == CV_32FC1 && before.size() == after.size(),
          "moved_fractions: the depth images must be CV_32FC1 of one size");
  require(change > 0 && std::isfinite(change), "moved_fractions: the change must be > 0");
  std::vector<double> out;
  out.reserve(masks.size());
  for (const cv::Mat& m : masks) {
    require(m.type() == CV_8U && m.size() == before.size(),
            "moved_fractions: the masks must be 8-bit of the depth images' size");
    int measured = 0;
    int moved = 0;
    for (int v = 0; v < m.rows; ++v) {
      const auto* in = m.ptr<uchar>(v);
      const auto* d0 = before.ptr<float>(v);
      const auto* d1 = after.ptr<float>(v);
      for (int u = 0; u < m.cols; ++u) {
        if (in[u] == 0 || !(d0[u] > 0) || !std::isfinite(d0[u])) continue;
        ++measured;
        const bool seen = d1[u] > 0 && std::isfinite(d1[u]);
        if (!seen || std::abs(static_cast<double>(d1[u]) - d0[u]) > change) ++moved;
      }
    }
    out.push_back(measured > 0 ? static_cast<double>(moved) / measured : 0.0);
  }
  return out;
}

std::vector<LearnCoverage> learn_coverage(const std::vector<std::string>& objects,
                                          const std::vector<LearnPush>& pushes) {
  std::vector<LearnCoverage> out;
  for (const std::string& name : objects) {
    LearnCoverage c{name, 0, 0};
    std::vector<int> turns;
    for (const LearnPush& p : pushes) {
      if (!p.executed || !p.truth || !p.truth->moved_intended || p.truth->intended != name) {
        continue;
      }
      ++c.pushes;
      if (std::find(turns.begin(), turns.end(), p.object) == turns.end()) turns.push_back(p.object);
    }
    c.turns = static_cast<int>(turns.size());
    out.push_back(c);
  }
  return out;
}

namespace {

// The simulated world's backdrop named by the options (sim::kBackgroundNames).
sim::Background background_of(const LearnOptions& o) {
  for (const auto& [name, value] : sim::kBackgroundNames) {
    if (name == o.background) return value;
  }
  throw Error("learn: --background must be " + core::choice_list(sim::kBackgroundNames) +
              " (it is '" + o.background + "')");
}

}  // namespace

void LearnOptions::validate() const {
  core::check_field_bounds(*this, "learn");
  colour.validate();
  if ((new_object == NewObjectScore::kColour || new_object == NewObjectScore::kPixels) &&
      known_margin >= 0) {
    throw Error(
        core::cat({"learn: --known-margin compares word likelihoods: not with --new-object ",
                   core::choice_name(new_object, kNewObjectScoreNames)}));
  }
  if (new_object == NewObjectScore::kPixels && views != LearnViews::kBefore &&
      views != LearnViews::kBoth) {
    throw Error(
        "learn: --new-object pixels compares the looks before the pushes: it needs --views "
        "before or both");
  }
  if (colour_words && oracle_ladder) {
    throw Error(
        "learn: --oracle-ladder needs --no-colour-words (the rungs' documents are SIFT words "
        "only)");
  }
  if (headline == LearnHeadline::kColour && !colour_words) {
    throw Error("learn: --headline colour scores by the colour words: it needs colour words");
  }
  if (ladder_pooled && !oracle_ladder) {
    throw Error(
        "learn: --ladder-pooled scores the oracle ladder's rungs: it needs --oracle-ladder");
  }
  if (revisit_top_down && (!(region_agree > 0) || passes < 2)) {
    throw Error(
        "learn: --revisit-top-down acts on region_agree's revisits: it needs --region-agree > 0 "
        "and --passes > 1");
  }
  if (moving_wait > 0 && candidates != LearnCandidates::kDepth && !depth) {
    throw Error(
        "learn: --moving-wait compares two looks' depth: it needs the depth image (--candidates "
        "depth or --depth)");
  }
  if (lost_rechoose && !(region_agree > 0)) {
    throw Error(
        "learn: --lost-rechoose acts on region_agree's lost object: it needs "
        "--region-agree > 0");
  }
  std::vector<std::string> all = parse_object_list(objects);
  for (const auto& c : names_or_empty(clutter)) {
    if (std::find(all.begin(), all.end(), c) != all.end()) {
      throw Error("learn: '" + c + "' is named twice (objects and clutter)");
    }
    all.push_back(c);
  }
  (void)background_of(*this);  // Error: an unknown backdrop
  features.validate();
  plan.validate();
  sparse.validate();
  dense.validate();
  words_model.validate();
  mot.validate();
}

namespace {

// The learner's state of one run.
class Learner {
 public:
  Learner(robot::Robot& robot, TableAttendant& attendant, int classes, const LearnOptions& o)
      : robot_(robot),
        attendant_(attendant),
        o_(o),
        classes_(classes),
        rng_(core::Rng::stream(o.seed, kChoiceStream)) {
    log_.open(o.out / "decisions.jsonl");
    models_.resize(static_cast<std::size_t>(classes));
    left_at_.resize(static_cast<std::size_t>(classes));
    region_of_.resize(static_cast<std::size_t>(classes));
    blob_of_.assign(static_cast<std::size_t>(classes), -1);
    aim_of_.assign(static_cast<std::size_t>(classes), std::nullopt);
    end_of_.resize(static_cast<std::size_t>(classes));
    own_.resize(static_cast<std::size_t>(classes));
  }

  // f() with its wall-clock and processor time added to `stage` (also when it throws).
  template <class F>
  auto timed(const std::string& stage, F f) {
    const StageClock clock(*this, stage);
    return f();
  }

  // Adds the wall-clock and processor time from its making to its end to a stage; the
  // perception stages' processor time also to the push being perceived (perception_cpu_).
  class StageClock {
   public:
    StageClock(Learner& l, std::string stage)
        : l_(l), stage_(std::move(stage)), t0_(Clock::now()), c0_(core::process_cpu_seconds()) {}
    StageClock(const StageClock&) = delete;
    StageClock& operator=(const StageClock&) = delete;
    StageClock(StageClock&&) = delete;
    StageClock& operator=(StageClock&&) = delete;
    ~StageClock() {
      const double cpu = core::process_cpu_seconds() - c0_;
      l_.seconds_[stage_] += std::chrono::duration<double>(Clock::now() - t0_).count();
      l_.cpu_[stage_] += cpu;
      if (stage_ == "segmentation" || stage_ == "words" || stage_ == "recognition")
        l_.perception_cpu_ += cpu;
    }

   private:
    Learner& l_;
    std::string stage_;
    Clock::time_point t0_;
    double c0_;
  };

  // The perception since the last executed push (its segmentation and words, the recognition
  // of the looks after it) becomes that push's; `next` (an executed push's index, or -1 at the
  // end) is perceived from now on.
  void perceive_next(int next) {
    if (perceived_ >= 0 && static_cast<std::size_t>(perceived_) < pushes_.size())
      pushes_[static_cast<std::size_t>(perceived_)].perception_cpu_seconds = perception_cpu_;
    perceived_ = next;
    perception_cpu_ = 0;
  }

  void run(bool progress) {
    core::ProgressBar bar(static_cast<std::size_t>(classes_ * o_.pushes * o_.passes),
                          "learn: pushing", progress);
    robot::Look first = timed("look", [&] { return robot_.look(); });
    const double scale = first.image.cols / 640.0;
    po_ = o_.plan;
    po_.grid_step = std::max(2, static_cast<int>(std::lround(o_.plan.grid_step * scale)));
    po_.patch = std::max(4, static_cast<int>(std::lround(o_.plan.patch * scale)));
    po_.blobs.sigma = o_.plan.blobs.sigma * scale;
    sparse_ = o_.sparse;
    sparse_.mask_fraction = o_.mask_fraction;
    // Pixel quantities of the sparse segmentation scale with the image (lambda is px^2).
    sparse_.evidence_step = std::max(3.0, o_.sparse.evidence_step * scale);
    sparse_.lambda = o_.sparse.lambda * scale * scale;
    sparse_.velocity_bandwidth = o_.sparse.velocity_bandwidth * scale;
    sparse_.density_sigma = std::max(2.0, o_.sparse.density_sigma * scale);
    wo_ = o_.words_model;
    wo_.density_sigma = std::max(2.0, o_.words_model.density_sigma * scale);
    centre_ = robot::pixel_to_table(
        first.camera, Eigen::Vector2d(first.image.cols / 2.0, first.image.rows / 2.0));
    write_png(o_.out / "table.png", first.image);
    log({.event = "start", .classes = classes_, .work_centre = xy(centre_)});
    current_ = std::move(first);
    // One turn a class; with rounds > C, a turn that gave its class no views leaves the class
    // for the next turn, until every class has views or the turns are spent.
    const int turns = std::max(classes_, o_.rounds);
    int c = 0;
    for (int turn = 0; turn < turns && c < classes_; ++turn) {
      if (turn >= classes_) {
        log({.event = "retry",
             .object = c,
             .why = core::cat({"turn ", std::to_string(turn + 1), " of ", std::to_string(turns),
                               ": the class has no views yet"})});
      }
      learn_object(c, bar);
      if (o_.rounds == 0 || class_views(c) > 0) ++c;
    }
    // passes: the classes with views again, fewest views first (ties by class), each from where
    // its object was left.
    for (int pass = 2; pass <= o_.passes; ++pass) {
      std::vector<int> order(static_cast<std::size_t>(classes_));
      std::iota(order.begin(), order.end(), 0);
      std::vector<int> views(order.size());
      for (const int r : order) views[static_cast<std::size_t>(r)] = class_views(r);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return views[static_cast<std::size_t>(a)] < views[static_cast<std::size_t>(b)];
      });
      for (const int r : order) revisit(r, pass, bar);
    }
    bar.finish();
    perceive_next(-1);
    log({.event = "end",
         .views = static_cast<int>(views_.size()),
         .blobs_out_of_reach = dropped_far_,
         .looks_split = splits_,
         .pushes = static_cast<int>(pushes_.size()),
         .faults = faults_});
  }

  // The mean log p(d) of the descriptors of `frames` under `om`'s words; nullopt when none.
  std::optional<double> own_mean_log_p(const ObjectModel& om,
                                       const std::vector<Eigen::MatrixXd>& frames) const {
    Eigen::Index rows = 0;
    for (const auto& f : frames) rows += f.rows();
    if (rows == 0) return std::nullopt;
    Eigen::MatrixXd x(rows, frames.front().cols());
    Eigen::Index at = 0;
    for (const auto& f : frames) {
      x.middleRows(at, f.rows()) = f;
      at += f.rows();
    }
    const double m = om.log_p_descriptors(x, wo_).mean();
    if (!std::isfinite(m)) return std::nullopt;
    return m;
  }

  // The views' colour words are made: for the documents or for (d)'s colour score.
  [[nodiscard]] bool colours_wanted() const {
    return o_.colour_words || o_.new_object == NewObjectScore::kColour;
  }

  // A training view of class c from push `push`: the features `f` found in `image` and, when
  // wanted, their colour words.
  [[nodiscard]] View view_of(int c, int push, const cv::Mat& image,
                             const features::Features& f) const {
    return {c, push, f.descriptors.clone(),
            colours_wanted() ? features::colour_words(image, f.keypoints, o_.colour)
                             : std::vector<std::int32_t>{}};
  }

  // new_object colour: log p(w | class k) of every colour word for each class k < c with
  // views (their colour words counted, add-one smoothed); an empty vector for a class without.
  [[nodiscard]] std::vector<Eigen::VectorXd> colour_log_p(int c) const {
    const int words = o_.colour.count();
    std::vector<Eigen::VectorXd> counts(static_cast<std::size_t>(c));
    for (const View& v : views_) {
      if (v.cls < 0 || v.cls >= c) continue;
      auto& n = counts[static_cast<std::size_t>(v.cls)];
      if (n.size() == 0) n = Eigen::VectorXd::Zero(words);
      for (const std::int32_t w : v.colours) n[w] += 1;
    }
    for (auto& n : counts) {
      if (n.size() == 0 || n.sum() == 0) {
        n.resize(0);
        continue;
      }
      n = ((n.array() + 1.0) / (n.sum() + words)).log().matrix();
    }
    return counts;
  }

  // new_object pixels: the colour words of `mask`'s pixels of `image` added to class c's.
  void add_pixel_colours(int c, const cv::Mat& image, const cv::Mat& mask) {
    const std::vector<double> v = features::colour_word_counts(image, mask, o_.colour);
    add_pixel_counts(
        c, Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  }
  // new_object pixels: colour-word counts added to class c's.
  void add_pixel_counts(int c, const Eigen::VectorXd& n) {
    if (pixel_colours_.size() <= static_cast<std::size_t>(c)) {
      pixel_colours_.resize(static_cast<std::size_t>(c) + 1);
    }
    Eigen::VectorXd& to = pixel_colours_[static_cast<std::size_t>(c)];
    if (to.size() == 0) to = Eigen::VectorXd::Zero(n.size());
    to += n;
  }

  // Training views of class c so far.
  [[nodiscard]] int class_views(int c) const {
    return static_cast<int>(
        std::count_if(views_.begin(), views_.end(), [c](const View& v) { return v.cls == c; }));
  }

  void log(const LearnDecision& d) {
    log_ << core::fields_to_json(d).dump() << '\n';
    log_.flush();
  }

  void fault(int c, const std::string& what, const std::string& message) {
    ++faults_;
    spdlog::debug("learn, object {}: {}: {}", c + 1, what, message);
    log({.event = "fault", .object = c, .fault = what, .message = message});
  }

  [[nodiscard]] const std::vector<LearnPush>& pushes() const { return pushes_; }
  [[nodiscard]] const std::vector<View>& views() const { return views_; }
  [[nodiscard]] const std::map<std::string, double>& seconds() const { return seconds_; }
  /// Processor seconds of the stages timed by this process (timed()).
  [[nodiscard]] const std::map<std::string, double>& cpu_seconds() const { return cpu_; }
  [[nodiscard]] int faults() const { return faults_; }
  [[nodiscard]] const std::map<std::string, int>& skips() const { return skips_; }
  [[nodiscard]] const std::vector<PredictiveLikelihood>& dirichlet_measure() const {
    return dirichlet_measure_;
  }
  std::map<std::string, double>& mutable_seconds() { return seconds_; }

 private:
  LookFeatures features_of(const cv::Mat& image, const cv::Mat& mask = {}) {
    const features::Features f = features::extract_features(image, o_.features, mask);
    LookFeatures lf;
    for (const auto& k : f.keypoints) lf.points.push_back(k.pt);
    lf.unit = f.empty() ? Eigen::MatrixXd(0, features::kDescriptorLength)
                        : unit_descriptors(f.descriptors);
    return lf;
  }

  // The look's putative objects within the arm's pushing reach (kPushReach); blobs beyond it
  // (distractors moving behind the work area) are dropped, counted in dropped_far_.
  planning::PlanningView plan_view() {
    planning::PlanningView v =
        timed("look", [&] { return planning::look_for_objects(current_, region_, po_); });
    if (o_.moving_wait > 0) view_depth_ = current_.depth;
    // 8.1.1: what moved with the arm in an object's last push is that object; a blob holding it
    // and more is split, the rest a putative object of its own.
    const std::size_t blobs = v.objects.size();
    std::vector<cv::Mat> regions = region_of_;
    for (cv::Mat& r : regions) {
      if (!r.empty() && (r.size() != v.image_size || r.type() != CV_8U)) r = cv::Mat();
    }
    points_.clear();
    if (o_.start_clearance > 0 && !current_.depth.empty()) {
      cv::Mat arm = current_.arm_mask;
      if (!arm.empty() && (arm.size() != current_.depth.size() || arm.type() != CV_8U)) {
        arm = cv::Mat();
      }
      const int step = std::max(1, current_.depth.cols / 320);
      points_ = timed("look", [&] {
        return depth_points(current_.depth, current_.camera, HandClearance{}.pusher_height, step,
                            arm);
      });
    }
    const bool by_depth = o_.candidates == LearnCandidates::kDepth && !current_.depth.empty();
    std::vector<int> found =
        by_depth ? depth_view(v, regions)
                 : planning::split_putative_objects(v, regions, o_.min_features, region_, po_);
    const std::size_t split = by_depth ? blobs : v.objects.size();
    // Then the blobs beyond the arm's reach are dropped (kept as obstacles only).
    const auto far = [](const planning::PutativeObject& o) {
      return o.centre.norm() > kPushReach || o.centre.x() < kBehindBase;
    };
    far_.clear();
    obstacles_.clear();
    std::vector<int> index(v.objects.size(), -1);
    std::vector<planning::PutativeObject> kept;
    for (std::size_t b = 0; b < v.objects.size(); ++b) {
      if (far(v.objects[b])) {
        far_.push_back(xy(v.objects[b].centre));
        obstacles_.push_back(std::move(v.objects[b]));
      } else {
        index[b] = static_cast<int>(kept.size());
        kept.push_back(std::move(v.objects[b]));
      }
    }
    v.objects = std::move(kept);
    dropped_far_ += static_cast<int>(far_.size());
    for (int& f : found) f = f >= 0 ? index[static_cast<std::size_t>(f)] : -1;
    if (o_.region_agree > 0) {
      // region_agree: a region names only a blob near where its push meant to put the object.
      for (std::size_t k = 0; k < found.size(); ++k) {
        if (found[k] >= 0 && !near_aim(k, v.objects[static_cast<std::size_t>(found[k])])) {
          const double off =
              (v.objects[static_cast<std::size_t>(found[k])].centre - *aim_of_[k]).norm();
          log({.event = "region-agree",
               .object = static_cast<int>(k),
               .blob = found[k],
               .why = core::printf_string(
                   "its region's blob lies %.3f m from its last push's target: not it", off)});
          found[k] = -1;
        }
      }
    }
    blob_of_ = found;
    if (split > blobs) {
      ++splits_;
      std::vector<KnownBlob> known;
      for (std::size_t k = 0; k < blob_of_.size(); ++k) {
        if (blob_of_[k] >= 0) known.push_back({static_cast<int>(k), blob_of_[k]});
      }
      log({.event = "split",
           .known = std::move(known),
           .blobs_before = static_cast<int>(blobs),
           .blobs_after = static_cast<int>(split)});
    }
    return v;
  }

  void relook() {
    current_ = timed("look", [&] { return robot_.look(); });
  }

  // LearnCandidates::kDepth: the putative objects of `v` become the look's depth candidates
  // (depth_candidates; each the part of the feature blobs inside it, table texture dropped) and
  // each known object the candidate its region overlaps most (known_candidates). Returns, per
  // object, its candidate (index into v.objects) or -1.
  std::vector<int> depth_view(planning::PlanningView& v, const std::vector<cv::Mat>& regions) {
    const double scale = current_.image.cols / 640.0;
    const int min_pixels =
        std::max(8, static_cast<int>(std::lround(kCandidatePixels * scale * scale)));
    cv::Mat arm = current_.arm_mask;
    if (!arm.empty() && (arm.size() != current_.depth.size() || arm.type() != CV_8U)) {
      arm = cv::Mat();
    }
    const std::vector<cv::Mat> cands = timed("look", [&] {
      return depth_candidates(current_.depth, current_.camera, o_.candidate_height,
                              o_.candidate_step, min_pixels, arm);
    });
    const std::size_t blobs = v.objects.size();
    const std::vector<int> of =
        planning::split_putative_objects(v, cands, o_.min_features, region_, po_);
    std::vector<planning::PutativeObject> kept;
    std::vector<cv::Mat> masks;
    std::vector<bool> used(v.objects.size(), false);
    int untextured = 0;
    for (std::size_t i = 0; i < cands.size(); ++i) {
      const int b = of[i];
      if (b < 0 || used[static_cast<std::size_t>(b)]) {
        ++untextured;  // too few features on it (or its features another candidate's)
        continue;
      }
      used[static_cast<std::size_t>(b)] = true;
      kept.push_back(v.objects[static_cast<std::size_t>(b)]);
      masks.push_back(cands[i]);
    }
    if (o_.candidate_footprint) {
      // The planner's footprint from the whole candidate's depth points (not only inside its
      // features' hull): the hand is not to come down on the untextured part of an object.
      cv::Mat depth = current_.depth;
      if (!arm.empty()) {
        depth = depth.clone();
        depth.setTo(0, arm);
      }
      for (std::size_t i = 0; i < kept.size(); ++i) {
        std::vector<cv::Point> on;
        cv::findNonZero(masks[i], on);
        std::vector<cv::Point> hull;
        cv::convexHull(on, hull);
        std::vector<Eigen::Vector2d> hull_px;
        hull_px.reserve(hull.size());
        for (const cv::Point& q : hull) hull_px.emplace_back(q.x, q.y);
        const cv::Rect box = cv::boundingRect(on);
        if (hull_px.size() < 3) continue;
        if (auto m = planning::measure_footprint(depth, current_.camera, hull_px, masks[i](box),
                                                 box, kFootprintStep)) {
          kept[i].centre = m->centre;
          kept[i].hull = std::move(m->hull);
          kept[i].height = m->height;
        }
      }
    }
    if (!wrote_candidates_) {
      cv::Mat1b labels(v.image_size, 0);
      for (std::size_t i = 0; i < masks.size(); ++i) {
        labels.setTo(static_cast<int>(255 - (i * 200) / std::max<std::size_t>(1, masks.size())),
                     masks[i]);
      }
      write_png(o_.out / "candidates.png", labels);
      wrote_candidates_ = true;
    }
    v.objects = std::move(kept);
    std::string held;
    std::vector<cv::Mat> agreed = regions;
    bool cut = false;  // region_agree cut a region
    if (o_.region_agree > 0) {
      // region_agree: a region does not name a candidate far from where its push meant to put
      // the object (its pixels on such a candidate are cut out of it).
      for (std::size_t r = 0; r < agreed.size(); ++r) {
        if (agreed[r].empty()) continue;
        for (std::size_t i = 0; i < masks.size(); ++i) {
          if (near_aim(r, v.objects[i])) continue;
          if (agreed[r].data == regions[r].data) agreed[r] = agreed[r].clone();
          agreed[r].setTo(0, masks[i]);
          cut = true;
        }
      }
    }
    std::vector<int> found = known_candidates(agreed, masks, end_of_);
    if (cut) {
      // The log names the candidates the cut re-assigned (the regions uncut name the same
      // candidates when nothing was cut).
      const std::vector<int> plain = known_candidates(regions, masks, end_of_);
      for (std::size_t r = 0; r < plain.size(); ++r) {
        if (plain[r] == found[r]) continue;
        held += core::cat({"; object ", std::to_string(r), "'s region: candidate ",
                           std::to_string(plain[r]), " -> ", std::to_string(found[r])});
      }
    }
    std::vector<KnownBlob> known;
    for (std::size_t k = 0; k < found.size(); ++k) {
      if (found[k] >= 0) known.push_back({static_cast<int>(k), found[k]});
    }
    log({.event = "candidates",
         .known = std::move(known),
         .blobs_before = static_cast<int>(blobs),
         .blobs_after = static_cast<int>(v.objects.size()),
         .by = core::cat({"depth: ", std::to_string(cands.size()), " candidates, ",
                          std::to_string(untextured), " without features", held})});
    return found;
  }

  // (a) / (d): the blob to learn next: the first at random; later the blob whose descriptors
  // are least likely under the object models so far (the largest mean log p(d) over the models
  // is least).
  int choose(int c, planning::PlanningView& view, const std::vector<Eigen::Vector2d>& tried) {
    const auto open_blobs = [&] {
      std::vector<int> open;
      for (int b = 0; b < static_cast<int>(view.objects.size()); ++b) {
        const bool was = std::any_of(tried.begin(), tried.end(), [&](const Eigen::Vector2d& t) {
          return (view.objects[static_cast<std::size_t>(b)].centre - t).norm() < kTrackRadius;
        });
        if (!was) open.push_back(b);
      }
      return open;
    };
    // moving_wait: the candidates whose depth moved while the robot held still (never chosen).
    const std::vector<int> moving = o_.moving_wait > 0 ? moving_blobs(c, view) : std::vector<int>();
    const auto is_moving = [&](int b) {
      return std::find(moving.begin(), moving.end(), b) != moving.end();
    };
    std::vector<int> open = open_blobs();
    // Why each candidate was not chosen (the first reason found).
    std::map<int, std::string> why_not;
    const auto skip = [&](int b, const std::string& reason) { why_not.emplace(b, reason); };
    const auto skipped = [&](int chosen) {
      std::vector<CandidateSkip> out;
      for (std::size_t f = 0; f < far_.size(); ++f) out.push_back({-1, "out-of-reach"});
      for (int b = 0; b < static_cast<int>(view.objects.size()); ++b) {
        if (b == chosen) continue;
        const auto it = why_not.find(b);
        out.push_back({b, it != why_not.end() ? it->second : "less-new"});
      }
      for (const CandidateSkip& k : out) ++skips_[k.reason];
      return out;
    };
    for (int b = 0; b < static_cast<int>(view.objects.size()); ++b) {
      if (std::find(open.begin(), open.end(), b) == open.end()) skip(b, "tried");
    }
    if (!moving.empty()) {
      for (const int b : moving) skip(b, "moving");
      std::erase_if(open, is_moving);
      if (open.empty()) {
        log({.event = "none-chosen", .object = c, .skipped = skipped(-1)});
        return -1;
      }
    }
    if (open.empty()) return -1;
    bool any = false;
    for (int k = 0; k < c; ++k) any = any || models_[static_cast<std::size_t>(k)].learned();
    if (!any) {
      int k = open[rng_.index(open.size())];
      if (o_.prefer_pushable) {
        // The drawn one first, then the others in a random order: the first pushable.
        std::vector<int> order = open;
        std::shuffle(order.begin(), order.end(), rng_.engine());
        std::stable_partition(order.begin(), order.end(), [&](int b) { return b == k; });
        k = -1;
        for (const int b : order) {
          if (const auto why = unpushable(view, b)) {
            skip(b, *why);
          } else {
            k = b;
            break;
          }
        }
        if (k < 0) k = order.front();  // none: the drawn one (its failures move on)
      }
      for (const int b : open) {
        if (b != k) skip(b, "not-drawn");
      }
      log({.event = "choose",
           .object = c,
           .blob = k,
           .why = "at random (7.2 a)",
           .skipped = skipped(k)});
      return k;
    }
    const LookFeatures lf = timed("recognition", [&] { return features_of(current_.image); });
    // The objects learned so far are known: where the learner left them, and where top-down
    // recognition finds them now; the choice is among the others (while any are left).
    std::vector<KnownBlob> known;
    for (int k = 0; k < c; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      std::vector<int> drop;
      if (blob_of_[ku] >= 0) {
        // Where its last push's motion segmentation put it (split from its neighbours).
        drop.push_back(blob_of_[ku]);
      } else {
        int b = -1;
        if (models_[ku].learned()) {
          const TopDownResult td = timed("recognition", [&] {
            return recognise_top_down(models_[ku], lf.points, lf.unit, current_.image.size(), wo_);
          });
          if (td.found) b = blob_on(view, td.mask);
          // 8.4-8.7: where top-down recognition finds it in a blob that holds more (objects
          // pushed together), the blob is split by the recognised region (unless it is another
          // object's segmented region): the rest stays a putative object to learn.
          const bool someones = std::find(blob_of_.begin(), blob_of_.end(), b) != blob_of_.end();
          if (b >= 0 && !someones) {
            cv::Mat region;
            cv::bitwise_and(
                features::dilated(td.mask, o_.dilate),
                blob_mask(view.objects[static_cast<std::size_t>(b)], current_.image.size()),
                region);
            const std::size_t before = view.objects.size();
            const std::vector<int> part =
                planning::split_putative_objects(view, {region}, o_.min_features, region_, po_);
            if (view.objects.size() > before && part[0] >= 0) {
              log({.event = "split",
                   .object = k,
                   .blobs_before = static_cast<int>(before),
                   .blobs_after = static_cast<int>(view.objects.size()),
                   .by = "top-down"});
              b = part[0];
            }
          }
        }
        if (b < 0 && left_at_[ku]) b = track(view, *left_at_[ku], kTrackRadius);
        if (b >= 0) drop.push_back(b);
      }
      for (int b : drop) known.push_back({k, b});
    }
    open = open_blobs();
    std::erase_if(open, is_moving);
    for (const auto& kn : known) {
      const auto it = std::find(open.begin(), open.end(), kn.blob);
      if (it != open.end()) open.erase(it);
      skip(kn.blob, "known");
    }
    if (open.empty()) {
      log({.event = "none-chosen", .object = c, .skipped = skipped(-1)});
      // Learning a known object again would give two classes of one object: move on instead.
      // (Pushing the least likely known blob anyway was tried on seed 1: six classes, five of
      // them the book, held out unchanged at 25%, 2.6 times the time.)
      fault(c, "only-known-objects", "every blob in view is an object learned already");
      return -1;
    }
    std::vector<BlobMeanLogP> scores;
    std::vector<std::pair<double, int>> ranked;  // (score, blob) of the new-looking candidates
    int best = -1;
    double best_s = std::numeric_limits<double>::infinity();
    const bool match = o_.new_object == NewObjectScore::kMatch;
    const bool colour = o_.new_object == NewObjectScore::kColour;
    const bool pixels = o_.new_object == NewObjectScore::kPixels;
    // "pixels": the classes' colour distributions from their looks before their pushes.
    std::vector<Eigen::VectorXd> class_pixels(static_cast<std::size_t>(c));
    for (int k = 0; k < c && pixels && static_cast<std::size_t>(k) < pixel_colours_.size(); ++k) {
      const Eigen::VectorXd& n = pixel_colours_[static_cast<std::size_t>(k)];
      if (n.size() > 0 && n.sum() > 0) class_pixels[static_cast<std::size_t>(k)] = n / n.sum();
    }
    // "match": each known object's views' descriptors (a stride sample of kMaxMatchPool).
    std::vector<cv::Mat> pools;
    if (match) pools = timed("recognition", [&] { return known_pools(c); });
    // "colour": the classes' colour models and the look's features' colour words.
    std::vector<Eigen::VectorXd> colour_models;
    std::vector<std::int32_t> look_colours;
    if (colour) {
      timed("recognition", [&] {
        colour_models = colour_log_p(c);
        std::vector<cv::KeyPoint> points;
        points.reserve(lf.points.size());
        for (const auto& p : lf.points) points.emplace_back(p, 1.0F);
        look_colours = features::colour_words(current_.image, points, o_.colour);
      });
    }
    const cv::Mat look = match ? float_rows(lf.unit) : cv::Mat();
    for (int b : open) {
      const auto& o = view.objects[static_cast<std::size_t>(b)];
      const cv::Mat m = blob_mask(o, current_.image.size());
      std::vector<Eigen::Index> rows;
      std::vector<int> others;  // the look's features outside the blob
      for (std::size_t i = 0; i < lf.points.size(); ++i) {
        const cv::Point p(static_cast<int>(lf.points[i].x), static_cast<int>(lf.points[i].y));
        if (p.inside(cv::Rect(0, 0, m.cols, m.rows)) && m.at<uchar>(p) != 0) {
          rows.push_back(static_cast<Eigen::Index>(i));
        } else {
          others.push_back(static_cast<int>(i));
        }
      }
      if (static_cast<int>(rows.size()) < o_.min_features) {
        skip(b, "no-features");
        continue;
      }
      Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), lf.unit.cols());
      for (std::size_t i = 0; i < rows.size(); ++i) {
        x.row(static_cast<Eigen::Index>(i)) = lf.unit.row(rows[i]);
      }
      std::optional<double> matched;
      std::optional<int> matched_object;
      if (match) {
        timed("recognition", [&] {
          const cv::Mat q = float_rows(x);
          cv::Mat rest(static_cast<int>(others.size()), look.cols, CV_32F);
          for (std::size_t i = 0; i < others.size(); ++i) {
            look.row(others[i]).copyTo(rest.row(static_cast<int>(i)));
          }
          for (int k = 0; k < c; ++k) {
            const cv::Mat& pool = pools[static_cast<std::size_t>(k)];
            if (pool.empty()) continue;
            const double f = descriptor_match_fraction(q, pool, rest, o_.match_ratio);
            if (!matched || f > *matched) {
              matched = f;
              matched_object = k;
            }
          }
        });
      }
      double s = -std::numeric_limits<double>::infinity();
      int s_object = -1;
      double below = 0;
      bool is_known = false;
      for (int k = 0; k < c && colour; ++k) {
        // The mean log p of the blob's colour words under class k's colours.
        const Eigen::VectorXd& lp = colour_models[static_cast<std::size_t>(k)];
        if (lp.size() == 0) continue;
        double sum = 0;
        for (const Eigen::Index r : rows) sum += lp[look_colours[static_cast<std::size_t>(r)]];
        const double sk = sum / static_cast<double>(rows.size());
        if (sk > s) {
          s = sk;
          s_object = k;
        }
      }
      if (pixels) {
        // Minus the Hellinger distance to the nearest class: the farthest blob is the least known.
        const std::vector<double> n = timed("recognition", [&] {
          return features::colour_word_counts(current_.image, m, o_.colour);
        });
        Eigen::VectorXd p =
            Eigen::Map<const Eigen::VectorXd>(n.data(), static_cast<Eigen::Index>(n.size()));
        if (p.sum() > 0) p /= p.sum();
        for (int k = 0; k < c; ++k) {
          const Eigen::VectorXd& q = class_pixels[static_cast<std::size_t>(k)];
          if (q.size() == 0) continue;
          const double sk = -hellinger(p, q);
          if (sk > s) {
            s = sk;
            s_object = k;
          }
        }
      }
      for (int k = 0; k < c && !colour && !pixels; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        const ObjectModel& om = models_[ku];
        if (!om.learned()) continue;
        const double sk = om.log_p_descriptors(x, wo_).mean();
        const double bk = own_[ku] ? sk - *own_[ku] : 0.0;
        if (sk > s) {
          s = sk;
          s_object = k;
          below = bk;
        }
        // Its words say it is object k: not a new object.
        if (o_.known_margin >= 0 && own_[ku] && bk >= -o_.known_margin && !is_known) {
          is_known = true;
          known.push_back({k, b});
        }
      }
      // Its descriptors say it is a known object: not a new object.
      if (match && o_.match_known < 1.0 && matched && *matched >= o_.match_known && !is_known) {
        is_known = true;
        known.push_back({*matched_object, b});
      }
      scores.push_back(
          {b, s, s_object, std::isfinite(below) ? below : 0.0, matched, matched_object});
      if (is_known) {
        skip(b, "known");
        continue;
      }
      // The least known: the fewest descriptors matched ("match"), else the least likely.
      const double score = match ? matched.value_or(0.0) : s;
      ranked.emplace_back(score, b);
      if (score < best_s) {
        best_s = score;
        best = b;
      }
    }
    if (o_.prefer_pushable && ranked.size() > 1) {
      // In the order of choice, the first candidate a push can be planned for.
      std::stable_sort(ranked.begin(), ranked.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      for (const auto& [score, b] : ranked) {
        if (const auto why = unpushable(view, b)) {
          skip(b, *why);
        } else {
          best = b;
          break;
        }
      }
      // None pushable: the least known anyway (its failures move on).
      if (why_not.count(best) > 0) {
        best = ranked.front().second;
        why_not.erase(best);
      }
    }
    if (best < 0) {
      if (!scores.empty() && (o_.known_margin >= 0 || (match && o_.match_known < 1.0))) {
        log({.event = "none-chosen", .object = c, .skipped = skipped(-1)});
      }
      if (o_.known_margin >= 0 && !scores.empty()) {
        fault(c, "only-known-objects",
              "every blob in view is an object learned already (by its words)");
        return -1;
      }
      if (match && o_.match_known < 1.0 && !scores.empty()) {
        fault(c, "only-known-objects",
              "every blob in view is an object learned already (by its descriptors)");
        return -1;
      }
      best = open.front();
    }
    log({.event = "choose",
         .object = c,
         .blob = best,
         .why = match    ? "fewest descriptors matched to the objects so far (7.2 d)"
                : colour ? "colour words least likely under the classes' colours so far (7.2 d)"
                : pixels ? "pixel colours farthest from the classes' looks so far (7.2 d)"
                         : "least likely under the object models so far (7.2 d)",
         .known = std::move(known),
         .scores = std::move(scores),
         .skipped = skipped(best)});
    return best;
  }

  // moving_wait: the robot holds still moving_wait s and looks again; `view` becomes the new
  // look's (plan_view; the choice is made on it, so that what is chosen is where it is now), and
  // its candidates whose depth moved since the look the old view was made from (view_depth_:
  // moved_fractions >= kMovingFraction) are returned, logged (`moving`: the new view's blobs,
  // their centres and each one's moved fraction).
  std::vector<int> moving_blobs(int c, planning::PlanningView& view) {
    if (view.objects.empty() || view_depth_.empty()) return {};
    const cv::Mat before = view_depth_;
    timed("look", [&] { robot_.hold_still(o_.moving_wait); });
    relook();
    dropped_far_ -= static_cast<int>(far_.size());  // the old view's are counted again
    view = plan_view();
    if (current_.depth.size() != before.size() || current_.depth.type() != before.type()) {
      return {};
    }
    std::vector<cv::Mat> masks;
    masks.reserve(view.objects.size());
    for (const auto& o : view.objects) masks.push_back(blob_mask(o, before.size()));
    const std::vector<double> moved = moved_fractions(before, current_.depth, masks);
    std::vector<int> out;
    std::string why = core::printf_string(
        "held still %.2f s, looked again (the blobs below); moved fraction by blob:",
        o_.moving_wait);
    std::vector<std::vector<double>> centres;
    for (std::size_t b = 0; b < moved.size(); ++b) {
      centres.push_back(xy(view.objects[b].centre));
      why += core::printf_string(" %zu:%.2f", b, moved[b]);
      if (moved[b] >= kMovingFraction) out.push_back(static_cast<int>(b));
    }
    log({.event = "moving",
         .object = c,
         .blobs = static_cast<int>(view.objects.size()),
         .centres = std::move(centres),
         .why = why});
    return out;
  }

  // prefer_pushable: why no push of candidate `b` can be planned (no-push-path, start-blocked),
  // or nothing when one can.
  std::optional<std::string> unpushable(const planning::PlanningView& view, int b) {
    const Eigen::Vector2d at = view.objects[static_cast<std::size_t>(b)].centre;
    const double approach = extra_approach_;  // a trial: the approach it grew is not kept
    const Sides s = plan_sides(view, b, at, push_target(view, b, at, 0.0));
    extra_approach_ = approach;
    if (s.clear) return std::nullopt;
    return std::string(s.blocked > 0 ? "start-blocked" : "no-push-path");
  }

  // Per object before c, its views' unit descriptors (a stride sample of kMaxMatchPool rows).
  [[nodiscard]] std::vector<cv::Mat> known_pools(int c) const {
    std::vector<cv::Mat> pools(static_cast<std::size_t>(c));
    for (int k = 0; k < c; ++k) {
      std::vector<cv::Mat> parts;
      int total = 0;
      for (const View& v : views_) {
        if (v.cls != k || v.descriptors.empty()) continue;
        parts.push_back(float_rows(unit_descriptors(v.descriptors)));
        total += parts.back().rows;
      }
      if (total == 0) continue;
      cv::Mat all;
      cv::vconcat(parts, all);
      const int stride = (total + kMaxMatchPool - 1) / kMaxMatchPool;
      cv::Mat pool(0, all.cols, CV_32F);
      for (int r = 0; r < all.rows; r += stride) pool.push_back(all.row(r));
      pools[static_cast<std::size_t>(k)] = pool;
    }
    return pools;
  }

  // region_agree: does blob `b` lie where object k's last push (the one that gave its region)
  // meant to put it? True when that push is unknown.
  [[nodiscard]] bool near_aim(std::size_t k, const planning::PutativeObject& b) const {
    return k >= aim_of_.size() || !aim_of_[k] || (b.centre - *aim_of_[k]).norm() <= o_.region_agree;
  }

  // Learned object c recognised top-down in the current look (logged `recognise`); `best`: the
  // blob its region lies on, or -1.
  TopDownResult top_down(int c, const planning::PlanningView& view, int& best) {
    TopDownResult td = timed("recognition", [&] {
      const LookFeatures lf = features_of(current_.image);
      return recognise_top_down(models_[static_cast<std::size_t>(c)], lf.points, lf.unit,
                                current_.image.size(), wo_);
    });
    best = td.found ? blob_on(view, td.mask) : -1;
    log({.event = "recognise",
         .object = c,
         .blob = best,
         .found = td.found,
         .kappa = td.kappa,
         .log_density = std::isfinite(td.log_density) ? td.log_density : 0.0,
         .features = td.features,
         .centre_px = xy(td.centre),
         .message = td.message});
    return td;
  }

  // region_agree: object c where its last push left it near its target: its region's blob
  // (plan_view keeps it only near that target; `how` "segmented"), else the blob nearest `at`
  // within region_agree ("held"); -1 when neither (`how` unchanged).
  int near_blob(int c, const planning::PlanningView& view, const Eigen::Vector2d& at,
                std::string& how) {
    if (const int b = blob_of_[static_cast<std::size_t>(c)]; b >= 0) {
      how = "segmented";
      return b;
    }
    if (const int b = track(view, at, o_.region_agree); b >= 0) {
      how = "held";
      return b;
    }
    return -1;
  }

  // Where is object c in the current look, `landing` where the turn's last push left it?
  // Top-down when it has a model, else by position.
  int locate(int c, const planning::PlanningView& view, const Eigen::Vector2d& last,
             Landing landing, std::string& how) {
    const ObjectModel& om = models_[static_cast<std::size_t>(c)];
    if (landing == Landing::kLost) {
      // The last push put it nowhere near its target: whatever lies there now is no better
      // than a neighbour; the turn moves on.
      how = "lost";
      return -1;
    }
    if (is_near(landing)) {
      // The last push left it near its target: its region's blob (which lies there), else the
      // blob nearest where it was found after the push.
      if (const int b = near_blob(c, view, last, how); b >= 0) return b;
    }
    if (is_held(landing)) {
      // Where the last push landed it (the blob nearest its target): held on to.
      if (const int b = track(view, last, kTrackRadius); b >= 0) {
        how = "held";
        return b;
      }
    }
    if (const int b = blob_of_[static_cast<std::size_t>(c)]; b >= 0) {
      how = "segmented";  // where its last push's motion segmentation left it
      return b;
    }
    if (om.learned()) {
      int best = -1;
      const TopDownResult td = top_down(c, view, best);
      if (best >= 0) {
        how = "top-down";
        return best;
      }
      fault(c, "recognition-found-nothing",
            td.found ? "the recognised region lies on no blob; tracking by position"
                     : td.message + "; tracking by position");
    }
    how = "tracked";
    const int near = track(view, last, kTrackRadius);
    if (near >= 0) return near;
    // Pushed into a neighbour, the two make one blob whose centre lies further away.
    const int merged = track(view, last, kLandRadius);
    if (merged >= 0) {
      how = "tracked-merged";
      log({.event = "refound",
           .object = c,
           .blob = merged,
           .why = "the nearest blob within the landing radius (merged with a neighbour?)"});
    }
    return merged;
  }

  planning::PushPlan plan(const planning::PlanningView& view, int blob,
                          const Eigen::Vector2d& target) {
    robot::ArmState arm(robot_.arm());
    planning::PushPlanOptions po = po_;
    // After a refusal (the hand would come down inside a tall object, whose features lie above
    // the table and make it look nearer than it is) approaches grow.
    po.max_approach = std::min(0.3, po.max_approach + extra_approach_);
    po.min_approach = std::min(po.max_approach, po.min_approach + extra_approach_);
    po.seed = core::stream_seed(o_.seed, kPlanStream, static_cast<std::uint64_t>(++plans_));
    // The blobs out of reach are no objects to learn but are there: the arm avoids them too.
    planning::PlanningView all = view;
    all.objects.insert(all.objects.end(), obstacles_.begin(), obstacles_.end());
    return planning::plan_push(all, blob, planning::PushGoal::kTarget, target, region_, arm,
                               robot_.joints(), po);
  }

  // Where to push the object (the table is not cleared, Ch 8): a short push, kPushStep, in the
  // direction (of kDirections, turned by `angle` so that it is pushed from ever other sides) that
  // keeps it furthest from the other blobs and inside the area the arm can push it again.
  Eigen::Vector2d push_target(const planning::PlanningView& view, int blob,
                              const Eigen::Vector2d& at, double angle) const {
    Eigen::Vector2d best = at;
    double best_score = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < kDirections; ++i) {
      const double a = angle + (2 * std::numbers::pi * i / kDirections);
      const Eigen::Vector2d t = at + kPushStep * Eigen::Vector2d(std::cos(a), std::sin(a));
      double gap = kCrowded;
      for (std::size_t b = 0; b < view.objects.size(); ++b) {
        if (static_cast<int>(b) == blob) continue;
        gap = std::min(gap, (view.objects[b].centre - t).norm());
      }
      const double off = off_area(t);
      // Ties (nothing near) go to the first direction: the golden-angle turn.
      // After a transit refusal, pushes toward the base are left last: their start lies beyond
      // the object, and the unfolding arm passes over it (and whatever stands between).
      const double inward = outward_only_ && at.norm() > 1e-9
                                ? std::max(0.0, -(t - at).normalized().dot(at.normalized()))
                                : 0.0;
      // keep_in_reach: a target outside the area only when no direction keeps it inside (the
      // gap is at most kCrowded, so kOutsideArea outweighs it).
      const double outside = o_.keep_in_reach && off > 0 ? kOutsideArea : 0.0;
      const double score = gap - (4 * off) - outside - inward - (1e-3 * i);
      if (score > best_score) {
        best_score = score;
        best = t;
      }
    }
    return best;
  }

  // How far a push target lies outside the area the arm can push an object again (kTargetReach,
  // kTargetNear, kTargetFront, kTargetSide about the view's centre line), m summed; 0 inside.
  [[nodiscard]] double off_area(const Eigen::Vector2d& t) const {
    return std::max(0.0, t.norm() - kTargetReach) + std::max(0.0, kTargetNear - t.norm()) +
           std::max(0.0, kTargetFront - t.x()) +
           std::max(0.0, std::abs(t.y() - centre_.y()) - kTargetSide);
  }

  // A push of `blob` (at `at`) toward `target`, else from the other sides (kSides, a side push
  // kSidePush long): the first planned whose start is clear (start_clear, hand_met).
  struct Sides {
    planning::PushPlan plan;
    int blocked = 0;     // sides planned but their start not clear
    int hand = 0;        // of them, those whose start the hand would meet (depth points)
    bool clear = false;  // the plan is planned and its start clear
  };
  Sides plan_sides(const planning::PlanningView& view, int blob, const Eigen::Vector2d& at,
                   const Eigen::Vector2d& target) {
    Sides out;
    // start_clearance: the planned side whose start the hand meets least, when none is clear.
    std::optional<planning::PushPlan> least;
    int least_met = std::numeric_limits<int>::max();
    const auto usable = [&](const planning::PushPlan& q) {
      if (q.outcome != planning::PlanOutcome::kPlanned) return false;
      if (!start_clear(view, q)) {
        ++out.blocked;
        return false;
      }
      if (const int met = hand_met(q); met >= kHandLeastPoints) {
        ++out.blocked;
        ++out.hand;
        if (met < least_met) {
          least_met = met;
          least = q;
        }
        return false;
      }
      return true;
    };
    const Eigen::Vector2d dir0 = target - at;
    const double a0 = std::atan2(dir0.y(), dir0.x());
    // With start_clearance, every side's start met by the hand: the approaches grow (up to
    // kMaxExtraApproach) and the sides are planned again.
    bool ok = false;
    for (;;) {
      out.plan = timed("plan", [&] { return plan(view, blob, target); });
      ok = usable(out.plan);
      // keep_in_reach: the sides whose push ends inside the area first (stable: in turn).
      std::vector<int> sides(kSides - 1);
      std::iota(sides.begin(), sides.end(), 1);
      const auto side_dir = [&](int side) {
        const double a = a0 + (side * 2 * std::numbers::pi / kSides);
        return Eigen::Vector2d(std::cos(a), std::sin(a));
      };
      if (o_.keep_in_reach) {
        std::stable_partition(sides.begin(), sides.end(), [&](int side) {
          return off_area(at + kSidePush * side_dir(side)) <= 0;
        });
      }
      for (const int side : sides) {
        if (ok) break;
        const Eigen::Vector2d dir = side_dir(side);
        if (outward_only_ && at.norm() > 1e-9 && dir.dot(at.normalized()) < -0.2) continue;
        if ((at + kSidePush * dir).x() < kTargetFront) continue;
        out.plan = timed("plan", [&] { return plan(view, blob, at + kSidePush * dir); });
        ok = usable(out.plan);
      }
      if (ok || !least || extra_approach_ >= kMaxExtraApproach) break;
      extra_approach_ = std::min(kMaxExtraApproach, extra_approach_ + kApproachStep);
    }
    if (!ok && least) out.plan = *least;
    out.clear = ok;
    return out;
  }

  // start_clearance: how many of the look's depth points the hand coming down to the push's
  // start meets (0 when off).
  [[nodiscard]] int hand_met(const planning::PushPlan& p) const {
    if (o_.start_clearance <= 0 || points_.empty()) return 0;
    HandClearance hc;
    hc.hand = o_.start_clearance;
    return hand_meets(points_, p.push.start, hc);
  }

  // The pusher comes down at the push's start: refused by the robot when the arm there would be
  // inside an object. A start seen on a blob (at the table or at the lift height) is not taken.
  bool start_clear(const planning::PlanningView& view, const planning::PushPlan& p) const {
    for (const double h : {0.0, 0.03, 0.06}) {
      const Eigen::Vector2d px =
          view.camera.project(Eigen::Vector3d(p.push.start.x(), p.push.start.y(), h));
      const cv::Point q(static_cast<int>(std::lround(px.x())),
                        static_cast<int>(std::lround(px.y())));
      for (const auto* list : {&view.objects, &obstacles_}) {
        for (const auto& o : *list) {
          const cv::Rect grown(o.box.x - 3, o.box.y - 3, o.box.width + 6, o.box.height + 6);
          if (!grown.contains(q)) continue;
          const cv::Point local(std::clamp(q.x - o.box.x, 0, o.box.width - 1),
                                std::clamp(q.y - o.box.y, 0, o.box.height - 1));
          if (o.mask(local) != 0) return false;
        }
      }
    }
    return true;
  }

  static LearnPushPlan plan_record(const planning::PlanningView& view,
                                   const planning::PushPlan& p) {
    const Eigen::Vector2d s =
        view.camera.project(Eigen::Vector3d(p.push.start.x(), p.push.start.y(), 0.0));
    const Eigen::Vector2d e =
        view.camera.project(Eigen::Vector3d(p.push.end.x(), p.push.end.y(), 0.0));
    return {s, e, p.push.start, p.push.end, p.target, std::isfinite(p.cost) ? p.cost : -1.0};
  }

  // Segments a push's episode; fills map/mask/frame of the scored frame and the views' masks
  // (frame index, mask) carried from it along the arm's motion after the touch.
  struct Segmented {
    cv::Mat1f map;
    cv::Mat1b mask;
    cv::Mat frame;
    std::vector<std::pair<int, cv::Mat>> view_masks;
    std::string message;
    cv::Point2d shift;   ///< the pusher's image motion from the touch to the last frame, px
    bool scene = false;  ///< the mask covered more than max_mask_share: refused, no views
  };

  // The arm's own image in frame `i` of a push's episode (loop/arm_image.hpp).
  cv::Mat1b arm_mask(const episode::Episode& e, int i, cv::Size size) {
    return detail::arm_image_mask(e, i, size, robot_.arm(), arm_state_);
  }

  Segmented segment(const fs::path& dir) {
    Segmented s;
    const episode::Episode e = episode::read_episode(dir);
    segmentation::MlResult ml;
    if (o_.segmentation == PushSegmentation::kSparse) {
      ml = segmentation::segment_ml_sparse(e, sparse_);
    } else {
      segmentation::MlOptions mo = o_.dense;
      mo.mask_fraction = o_.mask_fraction;
      mo.keep_frame_maps = true;
      ml = segmentation::segment_ml(e, mo);
    }
    s.message = ml.summary.message;
    if (ml.scored_frame < 0 || ml.map.empty() || cv::countNonZero(ml.mask) == 0) return s;
    // max_mask_share: a mask over much of the image is the scene (camera-motion residue, a map
    // with no peak), not one object; its views would teach the class the whole table.
    const double share = cv::countNonZero(ml.mask) / static_cast<double>(ml.mask.total());
    if (share > o_.max_mask_share) {
      s.message = core::printf_string(
          "the mask covers %.0f%% of the image (more than --max-mask-share %.2f): not one "
          "object, no views; %s",
          100 * share, o_.max_mask_share, ml.summary.message.c_str());
      s.scene = true;
      return s;
    }
    s.map = ml.map;
    s.mask = ml.mask.clone();
    s.mask.setTo(0, arm_mask(e, ml.scored_frame, s.mask.size()));
    s.frame = e.frame(ml.scored_frame);
    const int touch = ml.scored_frame;
    const auto at_touch = e.ee_image(touch);
    for (int i = touch; i < e.frame_count(); i += o_.view_step) {
      cv::Mat m;
      if (o_.segmentation == PushSegmentation::kDense &&
          i < static_cast<int>(ml.frame_maps.size())) {
        double hi = 0;
        cv::minMaxLoc(ml.map, nullptr, &hi);
        m = ml.frame_maps[static_cast<std::size_t>(i)] >= o_.mask_fraction * hi;
      } else {
        const auto at = e.ee_image(i);
        Eigen::Vector2d d = Eigen::Vector2d::Zero();
        if (at && at_touch) d = *at - *at_touch;
        const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, d.x(), 0, 1, d.y());
        cv::warpAffine(s.mask, m, shift, s.mask.size(), cv::INTER_NEAREST);
      }
      m.setTo(0, arm_mask(e, i, m.size()));
      const int in = cv::countNonZero(m);
      if (in > 0 && in <= o_.max_mask_share * static_cast<double>(m.total())) {
        s.view_masks.emplace_back(i, m);
      }
    }
    if (const auto a = e.ee_image(e.frame_count() - 1); a && at_touch) {
      s.shift = cv::Point2d(a->x() - at_touch->x(), a->y() - at_touch->y());
    }
    // keep the episode's frames for the views
    frames_.clear();
    for (const auto& [i, m] : s.view_masks) frames_.push_back(e.frame(i));
    return s;
  }

  // After a push of object c: c's region becomes what moved with the arm at the push's end (its
  // last view's mask, grown by dilate); another object's region that the push's motion overlapped
  // (a quarter of it or more) is forgotten: it may have moved (top-down recognition and its
  // position find it then). A push that segmented nothing changes nothing.
  void update_regions(int c, const Segmented& seg, const Eigen::Vector2d& end_px) {
    if (seg.view_masks.empty()) return;
    end_of_[static_cast<std::size_t>(c)] = cv::Point2d(end_px.x(), end_px.y());
    cv::Mat moved =
        seg.mask.empty() ? cv::Mat(current_.image.size(), CV_8U, cv::Scalar(0)) : seg.mask.clone();
    for (const auto& [i, m] : seg.view_masks) cv::bitwise_or(moved, m, moved);
    std::vector<int> forgotten;
    std::vector<int> carried;
    std::optional<LookFeatures> lf;
    std::optional<std::vector<cv::Mat>> pools;
    for (std::size_t k = 0; k < region_of_.size(); ++k) {
      cv::Mat& r = region_of_[k];
      if (static_cast<int>(k) == c || r.empty()) continue;
      const int area = cv::countNonZero(r);
      cv::Mat both;
      cv::bitwise_and(r, moved, both);
      if (area == 0 || 4 * cv::countNonZero(both) >= area) {
        if (o_.carry_regions && area > 0 && r.size() == current_.image.size()) {
          // Look for it by its descriptors: where it was, or moved with the push.
          if (!lf) lf = timed("recognition", [&] { return features_of(current_.image); });
          if (!pools) pools = timed("recognition", [&] { return known_pools(classes_); });
          cv::Mat out;
          const RegionFate fate = timed("recognition", [&] {
            return carry_region(r, seg.shift, lf->points, float_rows(lf->unit), (*pools)[k],
                                o_.match_ratio, kCarryMatched, out);
          });
          if (fate != RegionFate::kLost) {
            r = out;
            if (fate == RegionFate::kCarried) carried.push_back(static_cast<int>(k));
            continue;
          }
        }
        r = cv::Mat();
        forgotten.push_back(static_cast<int>(k));
      }
    }
    // Only the parts of the mask near where the pusher ended (within a quarter of the image's
    // width): motion elsewhere (the moving backdrop, a distractor) is not the object.
    cv::Mat1b last = seg.view_masks.back().second.clone();
    cv::Mat1i labels;
    const int parts = cv::connectedComponents(last, labels, 8, CV_32S);
    const double reach = last.cols / 4.0;
    std::vector<bool> keep(static_cast<std::size_t>(parts), false);
    for (int y = 0; y < last.rows; ++y) {
      for (int x = 0; x < last.cols; ++x) {
        const int l = labels(y, x);
        if (l > 0 && (Eigen::Vector2d(x, y) - end_px).norm() <= reach)
          keep[static_cast<std::size_t>(l)] = true;
      }
    }
    for (int y = 0; y < last.rows; ++y) {
      for (int x = 0; x < last.cols; ++x) {
        if (!keep[static_cast<std::size_t>(labels(y, x))]) last(y, x) = 0;
      }
    }
    cv::Mat region = features::dilated(last, o_.dilate);
    // An object carried along with c is not c: its region is cut out of c's.
    for (int k : carried) region.setTo(0, region_of_[static_cast<std::size_t>(k)]);
    region_of_[static_cast<std::size_t>(c)] = region;
    LearnDecision d{.event = "region",
                    .object = c,
                    .pixels = cv::countNonZero(region),
                    .forgotten = std::move(forgotten)};
    if (o_.carry_regions) d.carried = std::move(carried);
    log(d);
  }

  // The identity check of a turn's first push that gave views (LearnOptions::identity_margin):
  // per known object, the views' mean log p under its words and that less its own yardstick,
  // logged; the known object they are merged into (the best within the margin, while the turn
  // may still merge), else nullopt.
  std::optional<int> identity(int c, int index, int blob,
                              const std::vector<Eigen::MatrixXd>& frames, int merges) {
    std::vector<BlobMeanLogP> scores;
    std::optional<int> best;
    double best_below = -std::numeric_limits<double>::infinity();
    timed("recognition", [&] {
      for (int k = 0; k < c; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        if (!models_[ku].learned() || !own_[ku]) continue;
        const std::optional<double> sk = own_mean_log_p(models_[ku], frames);
        if (!sk) continue;
        const double below = *sk - *own_[ku];
        scores.push_back({blob, *sk, k, below});
        if (o_.identity_margin >= 0 && below >= -o_.identity_margin && below > best_below) {
          best_below = below;
          best = k;
        }
      }
    });
    if (scores.empty()) return std::nullopt;
    if (best && merges >= kMaxMerges) best.reset();
    LearnDecision d{.event = "identity", .object = c, .index = index, .blob = blob};
    d.scores = std::move(scores);
    if (best) {
      d.why = core::cat({"its views are object ", std::to_string(*best + 1),
                         "'s (within the identity margin): merged into it; the turn chooses "
                         "again"});
    }
    log(d);
    return best;
  }

  // A later pass's turn of class c (passes): its object where it was last left, logged
  // `revisit`; found, pushed again (learn_object), else skipped.
  void revisit(int c, int pass, core::ProgressBar& bar) {
    const auto cu = static_cast<std::size_t>(c);
    LearnDecision d{.event = "revisit", .object = c, .pass = pass};
    const auto skip = [&](const std::string& why) {
      d.why = why;
      log(d);
      bar.tick(static_cast<std::size_t>(o_.pushes));
    };
    if (class_views(c) == 0 || !models_[cu].learned()) return skip("the class has no views");
    if (!left_at_[cu]) return skip("where its object was left is unknown");
    const bool by_aim = o_.region_agree > 0 && aim_of_[cu];
    const Eigen::Vector2d at = by_aim ? *aim_of_[cu] : *left_at_[cu];
    d.at = xy(at);
    Revisit again{plan_view(), -1, "", pass};
    if (again.view.objects.empty()) return skip("no putative object in view");
    if (o_.region_agree > 0) {
      // Its region's blob (plan_view keeps it only near its aim), else the blob nearest its
      // last push's target within region_agree.
      again.blob = near_blob(c, again.view, at, again.how);
      if (again.blob < 0 && o_.revisit_top_down) {
        // revisit_top_down: not where it was left: where top-down recognition finds it.
        (void)top_down(c, again.view, again.blob);
        again.how = "top-down";
      }
      if (again.blob < 0) {
        return skip(core::cat({"no blob within ", core::printf_string("%.3f", o_.region_agree),
                               " m of its last push's target (nor its region)",
                               o_.revisit_top_down ? ", nor by top-down recognition" : ""}));
      }
    } else {
      again.blob = locate(c, again.view, at, Landing::kUnknown, again.how);
      if (again.blob < 0) return skip("not found (" + again.how + ")");
    }
    d.blob = again.blob;
    d.located = again.how;
    for (int j = 0; j < classes_; ++j) {
      if (j != c && blob_of_[static_cast<std::size_t>(j)] == again.blob) {
        return skip(
            core::cat({"found on object ", std::to_string(j + 1), "'s region (", again.how, ")"}));
      }
    }
    log(d);
    learn_object(c, bar, std::move(again));
  }

  // A turn of class c: a blob chosen (7.2 d) and pushed up to `pushes` times; `again` (passes):
  // a later pass's turn, its object found already (no choice, no identity check, views to c).
  void learn_object(int c, core::ProgressBar& bar, std::optional<Revisit> again = std::nullopt) {
    // A revisit's look is the turn's first (again->view is not read again).
    planning::PlanningView view = again ? std::move(again->view) : plan_view();
    if (!again) {
      std::vector<std::vector<double>> centres;
      for (const auto& b : view.objects) centres.push_back(xy(b.centre));
      log({.event = "look",
           .object = c,
           .blobs = static_cast<int>(view.objects.size()),
           .centres = std::move(centres),
           .out_of_reach = far_});
    }
    if (view.objects.empty()) {
      fault(c, "no-blobs", "no putative object in view; object skipped");
      bar.tick(static_cast<std::size_t>(o_.pushes));
      return;
    }
    extra_approach_ = 0;
    outward_only_ = false;
    // Blobs an earlier turn tried and got no views from are not chosen again (rounds > C).
    std::vector<Eigen::Vector2d> tried = given_up_;
    int k = again ? again->blob : choose(c, view, tried);
    if (k < 0) {
      bar.tick(static_cast<std::size_t>(o_.pushes));
      return;
    }
    if (!again) attendant_.chose(c, view, k);
    // The views' push numbers (counted once per push) follow the class's earlier passes'.
    int base = 0;
    if (again) {
      for (const View& v : views_) {
        if (v.cls == c) base = std::max(base, v.push + 1);
      }
    }
    Eigen::Vector2d last = view.objects[static_cast<std::size_t>(k)].centre;
    int failures = 0;                          // pushes in a row not planned or refused
    std::string last_failure = "not-planned";  // the last failure's kind (CandidateSkip)
    double angle = rng_.uniform(-std::numbers::pi, std::numbers::pi);
    int done = 0;
    int attempts = 0;
    bool first = true;
    Landing landing = Landing::kUnknown;  // where the turn's last executed push left its object
    bool checked = again.has_value();     // the identity check of the turn's first push with views
    int merges = 0;  // the turn's pushes merged into known objects (identity_margin)
    // The turn starts again on blob k of the view (logged "rechoose", why).
    const auto rechoose = [&](const std::string& why, const std::vector<CandidateSkip>& skipped) {
      log({.event = "rechoose", .object = c, .blob = k, .why = why, .skipped = skipped});
      attendant_.chose(c, view, k);
      last = view.objects[static_cast<std::size_t>(k)].centre;
      failures = 0;
      extra_approach_ = 0;
      first = true;
      landing = Landing::kUnknown;
    };
    while (done < o_.pushes && attempts < 2 * o_.pushes + 4) {
      ++attempts;
      if (!first) view = plan_view();
      if (failures >= kMaxFailures && (done > 0 || again)) {
        // Pushed out of reach or where the hand cannot come down: what was learned is kept.
        fault(c, "stuck",
              core::cat({std::to_string(kMaxFailures),
                         " pushes in a row could not be planned or were refused "
                         "after ",
                         std::to_string(done), " pushes; moving on"}));
        break;
      }
      if (failures >= kMaxFailures && done == 0) {
        // The object cannot be pushed (out of reach, or the hand would come down on it):
        // another blob instead, logged.
        tried.push_back(last);
        ++skips_[last_failure];
        const std::vector<CandidateSkip> given_up{{k, last_failure}};
        k = choose(c, view, tried);
        if (k < 0) {
          fault(c, "no-pushable-object", "every blob in view was tried; moving on");
          break;
        }
        rechoose("three pushes in a row could not be planned or were refused", given_up);
      }
      std::string how = again ? again->how : "chosen";
      const int blob = first ? k : locate(c, view, last, landing, how);
      first = false;
      if (blob < 0 && how == "lost" && o_.lost_rechoose && !again) {
        // lost_rechoose: the turn's remaining pushes go to a blob chosen again (7.2 d).
        fault(c, "lost",
              "region_agree: no blob near where the last push meant to put the object; "
              "choosing again");
        k = choose(c, view, tried);
        if (k < 0) break;
        rechoose("region_agree: lost (no blob near the last push's target): chosen again", {});
        continue;
      }
      if (blob < 0) {
        fault(c, "lost",
              how == "lost" ? "region_agree: no blob near where the last push meant to put the "
                              "object; moving on"
                            : "the object is no longer in view (off the table or out of reach)");
        break;
      }
      last = view.objects[static_cast<std::size_t>(blob)].centre;
      const Eigen::Vector2d target = push_target(view, blob, last, angle);
      angle += kGoldenAngle;
      const Sides sides = plan_sides(view, blob, last, target);
      const planning::PushPlan& p = sides.plan;
      if (sides.blocked > 0) {
        LearnDecision d{.event = "replan",
                        .object = c,
                        .why = "the pusher would come down on a blob",
                        .sides_rejected = sides.blocked};
        if (sides.hand > 0) d.sides_hand = sides.hand;
        log(d);
      }
      if (p.outcome != planning::PlanOutcome::kPlanned) {
        fault(c, "not-planned", core::cat({"no side could be pushed: ", p.message}));
        ++failures;
        last_failure = sides.blocked > 0 ? "start-blocked" : "not-planned";
        extra_approach_ = 0;  // the grown approach may be to blame
        relook();
        continue;
      }
      LearnPush lp;
      lp.index = static_cast<int>(pushes_.size());
      lp.object = c;
      lp.dir = core::printf_string("pushes/push_%03d", lp.index);
      lp.plan = plan_record(view, p);
      lp.located = how;
      if (again) lp.pass = again->pass;
      const fs::path dir = o_.out / lp.dir;
      fs::create_directories(dir);
      write_png(dir / "before.png", current_.image);
      // views before: the look and the pushed blob, kept for the view.
      struct {
        cv::Mat image;
        cv::Mat mask;
      } before;
      if (o_.views == LearnViews::kBefore || o_.views == LearnViews::kBoth) {
        before.image = current_.image;
        before.mask =
            blob_mask(view.objects[static_cast<std::size_t>(blob)], current_.image.size());
      }
      PushIntent in{c, "learn", lp.index, &view, blob, &p};
      attendant_.before_push(in);
      robot::PushRecording rec;
      rec.episode_dir = dir / "episode";
      rec.overwrite = true;
      rec.fps = o_.fps;
      std::string message;
      try {
        const robot::PushReport rep = timed("push", [&] { return robot_.push(p.push, rec); });
        lp.executed = true;
        lp.frames = rep.frames;
        lp.robot_seconds = rep.seconds;
        seconds_["push_robot_clock"] += rep.seconds;  // how long the push lasted for the robot
        perceive_next(lp.index);
        message = rep.message;
      } catch (const Error& e) {
        message = e.what();
      }
      attendant_.after_push(in, lp.executed);
      log({.event = "push",
           .object = c,
           .index = lp.index,
           .blob = blob,
           .located = how,
           .plan = lp.plan,
           .executed = lp.executed,
           .message = message});
      if (!lp.executed) {
        fault(c, "robot-refused", message);
        ++failures;
        last_failure =
            message.find("transit") != std::string::npos ? "transit-refused" : "robot-refused";
        if (message.find("transit") != std::string::npos) outward_only_ = true;
        extra_approach_ = std::min(kMaxExtraApproach, extra_approach_ + kApproachStep);
        lp.outcome = "refused: " + message;
        pushes_.push_back(lp);
        relook();
        continue;
      }
      failures = 0;
      relook();
      write_png(dir / "after.png", current_.image);
      const Segmented seg = timed("segmentation", [&] { return segment(dir / "episode"); });
      cv::Mat last_mask;
      // views after/before: the push's motion views, held back (after: taken when the look
      // after the push gives no view).
      struct MotionView {
        View view;
        int frame;
        cv::Mat mask;
      };
      std::vector<MotionView> motion;
      std::vector<Eigen::MatrixXd> frames;
      if (seg.map.empty()) {
        if (seg.scene) {
          fault(c, "mask-is-the-scene", seg.message);
        } else {
          fault(c, "moved-nothing",
                "segmentation found nothing moving with the arm: " + seg.message);
        }
        lp.outcome = "nothing segmented: " + seg.message;
        const cv::Mat1b zero(current_.image.size(), 0);
        write_png(dir / "map.png", zero);
        write_png(dir / "mask.png", zero);
        write_png(dir / "frame.png", current_.image);
      } else {
        cv::Mat map8;
        seg.map.convertTo(map8, CV_8U, 255.0);
        write_png(dir / "map.png", map8);
        write_png(dir / "mask.png", seg.mask);
        write_png(dir / "frame.png", seg.frame);
        timed("words", [&] {
          for (std::size_t v = 0; v < seg.view_masks.size(); ++v) {
            const cv::Mat m = features::dilated(seg.view_masks[v].second, o_.dilate);
            const features::Features f = features::extract_features(frames_[v], o_.features, m);
            if (f.size() < o_.min_features) continue;
            frames.push_back(unit_descriptors(f.descriptors));
            last_mask = seg.view_masks[v].second;
            View taken = view_of(c, base + done, frames_[v], f);
            if (o_.views == LearnViews::kAfter || o_.views == LearnViews::kBefore) {
              // The look after (or before) the push gives the view (after: these its stand-in).
              motion.push_back({std::move(taken), seg.view_masks[v].first, last_mask});
              continue;
            }
            views_.push_back(std::move(taken));
            attendant_.view_taken(in, dir / "episode", seg.view_masks[v].first,
                                  seg.view_masks[v].second);
            ++lp.views;
          }
        });
        lp.outcome = core::cat({std::to_string(lp.views), " views; ", seg.message});
      }
      // Identity check (LearnOptions::identity_margin): is the turn's first push with views of
      // an object learned already? Then the push is that object's (its views, words, region).
      std::optional<int> same;
      if (!checked && !frames.empty() && c > 0) {
        checked = true;
        same = identity(c, lp.index, blob, frames, merges);
      }
      const int owner = same ? *same : c;
      update_regions(owner, seg,
                     view.camera.project(Eigen::Vector3d(p.push.end.x(), p.push.end.y(), 0.0)));
      if (!seg.view_masks.empty()) aim_of_[static_cast<std::size_t>(owner)] = p.target;
      // Did the object move? Where its motion segmentation left it, else near the plan's target,
      // else where it was.
      const planning::PlanningView after = plan_view();
      int now = -1;
      bool held = false;
      if (o_.hold_target && !same) {
        // The blob nearest where the push meant to land it, before its segmented region.
        now = track(after, p.target, kHoldRadius);
        held = now >= 0;
      }
      if (now < 0) now = blob_of_[static_cast<std::size_t>(owner)];
      landing = held ? Landing::kHeld : Landing::kUnknown;
      if (o_.region_agree > 0 && !same) {
        // region_agree: its region's blob lies near the target (or it has none); else the blob
        // nearest the target, within region_agree.
        if (now < 0) now = track(after, p.target, o_.region_agree);
        const bool near =
            now >= 0 && (after.objects[static_cast<std::size_t>(now)].centre - p.target).norm() <=
                            o_.region_agree;
        landing = !near ? Landing::kLost : held ? Landing::kNearHeld : Landing::kNear;
        if (!near) {
          // No blob near where the push meant to put it (off the table, out of reach, merged
          // with a neighbour): lost; where it was meant to be is where it was left.
          now = -1;
          last = p.target;
        }
      }
      const bool lost = landing == Landing::kLost;
      if (now < 0 && !lost) now = track(after, p.target, kLandRadius);
      if (now < 0 && !lost) now = track(after, last, kTrackRadius);
      if (now >= 0 &&
          (after.objects[static_cast<std::size_t>(now)].centre - last).norm() < kStill) {
        fault(c, "moved-nothing", "the push left the object where it was");
      }
      if (now >= 0) last = after.objects[static_cast<std::size_t>(now)].centre;
      // views both: the push's motion views (taken above) and its before view, entered once a
      // motion view so that it weighs as much as all of them.
      const bool both = o_.views == LearnViews::kBoth && lp.views > 0;
      if ((o_.views == LearnViews::kBefore && !motion.empty()) || both) {
        // views before: the look before the push, cut out by the blob it was planned on.
        const features::Features f = timed("words", [&] {
          return masked_features(before.image, before.mask, o_.features, o_.dilate);
        });
        const int copies = both ? lp.views : 1;
        if (f.size() >= o_.min_features) {
          if (o_.new_object == NewObjectScore::kPixels) {
            add_pixel_colours(c, before.image, before.mask);
          }
          const View taken = view_of(c, base + done, before.image, f);
          for (int i = 0; i < copies; ++i) {
            views_.push_back(taken);
            // Its truth: the episode's first frame (nothing pushed yet).
            attendant_.view_taken(in, dir / "episode", 0, before.mask);
          }
          if (!both) last_mask = before.mask;
          lp.outcome = both ? core::cat({std::to_string(lp.views),
                                         " views and the look before the "
                                         "push weighing as many; ",
                                         seg.message})
                            : core::cat({"1 view (the look before the push); ", seg.message});
          lp.views = both ? 2 * lp.views : 1;
        } else if (!both) {
          lp.views = 0;
          lp.outcome = core::cat({"no view: the pushed blob has too few features; ", seg.message});
        }
      }
      if (o_.views == LearnViews::kAfter && !motion.empty()) {
        // views after: the look after the push, cut out by the blob where the learner believes
        // its object lies; when it has none there (lost, or too few features), the push's
        // motion views as before.
        features::Features f;
        cv::Mat m;
        if (now >= 0 && !lost) {
          m = blob_mask(after.objects[static_cast<std::size_t>(now)], current_.image.size());
          f = timed("words",
                    [&] { return masked_features(current_.image, m, o_.features, o_.dilate); });
        }
        if (!m.empty() && f.size() >= o_.min_features) {
          views_.push_back(view_of(c, base + done, current_.image, f));
          attendant_.view_taken(in, {}, -1, m);
          last_mask = m;
          lp.views = 1;
          lp.outcome = core::cat({"1 view (the look after the push); ", seg.message});
        } else {
          for (MotionView& v : motion) {
            views_.push_back(std::move(v.view));
            attendant_.view_taken(in, dir / "episode", v.frame, v.mask);
          }
          lp.views = static_cast<int>(motion.size());
          lp.outcome =
              core::cat({std::to_string(lp.views),
                         " views (its motion's: no blob of it after the push); ", seg.message});
        }
      }
      attendant_.views_taken(in, lp.views, last_mask);
      if (same) {
        // Merged: the known object takes the push (as a later push of it); the turn's class
        // stays empty and the turn chooses again among the others.
        const auto su = static_cast<std::size_t>(*same);
        timed("words", [&] {
          models_[su].later_push(frames, wo_, rng_);
          own_[su] = own_mean_log_p(models_[su], frames);
        });
        for (View& v : views_) {
          if (v.cls == c) v.cls = *same;
        }
        // new_object pixels: the push's looks go with its views.
        if (static_cast<std::size_t>(c) < pixel_colours_.size() &&
            pixel_colours_[static_cast<std::size_t>(c)].size() > 0) {
          const Eigen::VectorXd moved = pixel_colours_[static_cast<std::size_t>(c)];
          pixel_colours_[static_cast<std::size_t>(c)].resize(0);
          add_pixel_counts(*same, moved);
        }
        left_at_[su] = last;
        ++merges;
        lp.outcome += core::cat({"; merged into object ", std::to_string(*same + 1)});
        pushes_.push_back(lp);
        bar.tick();
        view = plan_view();
        // The merged object is known now (its region, where it was left): not chosen again.
        const std::vector<CandidateSkip> merged{{blob, "known"}};
        k = choose(c, view, tried);
        if (k < 0) break;
        rechoose(core::cat({"identity: the pushed object is object ", std::to_string(*same + 1)}),
                 merged);
        checked = false;
        done = 0;
        attempts = 0;
        continue;
      }
      // Object words and their Dirichlet (8.1.2).
      ObjectModel& om = models_[static_cast<std::size_t>(c)];
      timed("words", [&] {
        if (const auto ll = om.predictive_log_likelihood(frames, wo_)) {
          dirichlet_measure_.push_back({c, base + done, ll->first, ll->second});
        }
        if (!frames.empty()) {
          if (om.learned())
            om.later_push(frames, wo_, rng_);
          else
            (void)om.first_push(frames, wo_, rng_);
          // Its own views' mean log p under its words (the yardstick of known_margin).
          if (om.learned()) own_[static_cast<std::size_t>(c)] = own_mean_log_p(om, frames);
        }
      });
      log({.event = "views",
           .object = c,
           .index = lp.index,
           .views = lp.views,
           .words = om.learned() ? om.num_words() : 0,
           .segmentation = seg.message});
      pushes_.push_back(lp);
      ++done;
      bar.tick();
    }
    left_at_[static_cast<std::size_t>(c)] = last;
    if (o_.rounds > 0 && class_views(c) == 0 && !again) {
      // Every blob this turn tried gave nothing: later turns choose others.
      given_up_ = tried;
      given_up_.push_back(last);
      // A class with no views has no model: where it was left names no object.
      left_at_[static_cast<std::size_t>(c)].reset();
    }
    if (done < o_.pushes) {
      bar.tick(static_cast<std::size_t>(o_.pushes - done));
      log({.event = "move-on",
           .object = c,
           .why = core::cat({"only ", std::to_string(done), " pushes succeeded"})});
    }
  }

  robot::Robot& robot_;
  TableAttendant& attendant_;
  const LearnOptions& o_;
  int classes_;
  core::Rng rng_;
  std::ofstream log_;
  planning::TableRegion region_;
  planning::PushPlanOptions po_;
  segmentation::SparseOptions sparse_;
  ObjectWordOptions wo_;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  robot::Look current_;
  std::vector<ObjectModel> models_;
  std::vector<std::optional<Eigen::Vector2d>> left_at_;  ///< where each object was left, m
  /// Per object, where it lies in the current look (8-bit, the image's size): what moved with
  /// the arm at the end of its last push; empty when unknown (or moved since by another push).
  std::vector<cv::Mat> region_of_;
  std::vector<int> blob_of_;  ///< per object, its putative object in the last plan_view, or -1
  /// candidates.png (the first look's depth candidates) written.
  bool wrote_candidates_ = false;
  /// moving_wait: the depth image of the look the last plan_view was made from (else empty).
  cv::Mat view_depth_;
  /// Per object, where the pusher ended in its last push that gave a region (image px).
  std::vector<std::optional<cv::Point2d>> end_of_;
  int splits_ = 0;  ///< looks in which a blob was split by an object's region
  /// start_clearance: the last look's depth points above the table (x, y, height, m).
  std::vector<Eigen::Vector3d> points_;
  /// Per reason, the candidates skipped at the run's choices (CandidateSkip).
  std::map<std::string, int> skips_;
  /// Per class, its last push's views' mean log p under its words (known_margin's yardstick).
  std::vector<std::optional<double>> own_;
  /// Where turns that gave their class no views left their blob, m: not chosen again.
  std::vector<Eigen::Vector2d> given_up_;
  std::vector<LearnPush> pushes_;
  std::vector<View> views_;
  /// new_object pixels: per class, its pushed blob's pixels' colour-word counts in the look
  /// before each push that gave it a view (empty: none yet).
  std::vector<Eigen::VectorXd> pixel_colours_;
  std::vector<cv::Mat> frames_;
  std::map<std::string, double> seconds_;
  std::map<std::string, double> cpu_;  ///< processor seconds per stage (timed())
  int perceived_ = -1;                 ///< the executed push being perceived (perceive_next)
  double perception_cpu_ = 0;          ///< its perception's processor seconds so far
  std::vector<PredictiveLikelihood> dirichlet_measure_;
  int faults_ = 0;
  int plans_ = 0;
  int dropped_far_ = 0;                   ///< blobs out of the arm's pushing reach, over all looks
  std::vector<std::vector<double>> far_;  ///< the last look's blobs out of reach (centres, m)
  /// The last look's blobs out of reach: not to learn, but the arm's paths avoid them.
  std::vector<planning::PutativeObject> obstacles_;
  /// region_agree: per object, the planned target of its last push that gave it a region, m.
  std::vector<std::optional<Eigen::Vector2d>> aim_of_;
  double extra_approach_ = 0;  ///< m, grown after each refusal of the object's pushes
  /// The object's transit was refused: pushes away from the base are preferred (their start lies
  /// between the base and the object, reached without passing over it).
  bool outward_only_ = false;
  std::optional<robot::ArmState> arm_state_;  ///< the arm's kinematics, for arm_mask
};

// Everything a run leaves besides the JSON: the learner's record, the models, the views' theta.
// The held-out views' documents of each object, as score_self_supervision renders them (alone
// at the table's centre, yaw stepped through 360 degrees, the ground-truth mask, views with at
// least min_features features): one simulated table at a time.
std::vector<topics::Corpus> held_out_documents(const LearnOptions& o,
                                               const std::vector<std::string>& objects,
                                               const features::Vocabulary& vocabulary) {
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  std::vector<topics::Corpus> held;
  held.reserve(objects.size());
  for (const std::string& name : objects) {
    sim::TableOptions table;
    table.objects = {name};
    table.seed = o.seed;
    table.width = o.width;
    table.height = o.height;
    sim::SimulatedRobot alone(table, catalogue);
    const int id = alone.ground_truth().at(0).id;
    const auto colour = o.document_colour();
    topics::Corpus corpus(features::document_vocabulary_size(vocabulary, colour));
    for (int v = 0; v < o.held_out; ++v) {
      const HeldOutView view = render_held_out_view(alone, name, id, v, o.held_out);
      const features::Features f = masked_features(view.image, view.mask, o.features, o.dilate);
      if (f.size() < o.min_features) continue;
      corpus.add_tokens(features::document_words(vocabulary, view.image, f, colour));
    }
    held.push_back(std::move(corpus));
  }
  return held;
}

struct Core {
  std::unique_ptr<Learner> learner;
  Learning learning;
  std::optional<topics::Corpus> training;  ///< the robot's views' documents (model order)
  std::vector<int> training_labels;        ///< their model classes (-1: class left out)
  std::optional<topics::LdaModel> lda;
  std::optional<features::Vocabulary> vocabulary;
  int classes = 0;
};

// What marks a run directory proprio learn wrote: its result, or its marker and decision log.
constexpr std::string_view kLearnMarkers[] = {"learn.json", "INCOMPLETE", "decisions.jsonl"};

// The run directory is written under a hidden name beside --out (`w` is `o` with out = that
// name) and swapped in whole by commit_out (issue 16): a failed or killed run leaves an older
// run as it was, and none of the older run's files stay in the new one.
std::unique_ptr<core::StagedDirectory> prepare_out(const LearnOptions& o, LearnOptions& w) {
  if (o.out.empty()) throw Error("learn: --out (the run directory) is required");
  if (fs::exists(o.out) && !o.overwrite) {
    throw Error(o.out.string() + ": already exists (use --overwrite to replace it)");
  }
  auto staged = std::make_unique<core::StagedDirectory>(o.out, o.overwrite, kLearnMarkers);
  w = o;
  w.out = staged->staging_path();
  fs::create_directories(w.out / "pushes");
  core::write_file_atomic(w.out / "INCOMPLETE", "proprio learn is running or was interrupted\n");
  return staged;
}

// The loop, then the vocabulary, LDA and the Mixture of Topics over the robot's views.
void learn_core(Core& k, const LearnOptions& o, robot::Robot& robot, TableAttendant& attendant,
                const core::Provenance& provenance) {
  k.learner = std::make_unique<Learner>(robot, attendant, k.classes, o);
  Learner& l = *k.learner;
  l.run(o.progress);
  const auto& views = l.views();
  Learning& g = k.learning;
  g.classes = k.classes;
  for (int c = 0; c < k.classes; ++c) {
    g.class_names.push_back(core::cat({"object_", std::to_string(c + 1)}));
  }
  g.views_per_class.assign(static_cast<std::size_t>(k.classes), 0);
  if (views.empty()) {
    l.log({.event = "no-views", .why = "no push gave a view: no model"});
    return;
  }
  // Vocabulary: given, or k-means over the descriptors of every view (no sample; all cores).
  if (!o.vocabulary.empty()) {
    k.vocabulary = features::read_vocabulary(o.vocabulary);
  } else {
    l.timed("vocabulary", [&] {
      std::vector<cv::Mat> all;
      all.reserve(views.size());
      for (const auto& v : views) all.push_back(v.descriptors);
      k.vocabulary = views_vocabulary(all, o.words, o.seed, 0, 0);
    });
  }
  features::write_vocabulary(o.out / "vocabulary.vocab", *k.vocabulary, provenance);
  // With colour words each view's document is its SIFT words, then its colour words numbered
  // after the vocabulary's.
  const int words = features::document_vocabulary_size(*k.vocabulary, o.document_colour());
  topics::Corpus corpus(words);
  for (const auto& v : views) {
    std::vector<std::int32_t> doc = features::bag_of_words(*k.vocabulary, v.descriptors);
    if (o.colour_words)
      doc = features::with_colour_words(std::move(doc), v.colours, k.vocabulary->size());
    corpus.add_tokens(doc);
  }
  if (!o.lda_model.empty()) {
    k.lda = topics::load_lda_model(o.lda_model);
    if (k.lda->num_words() != words) {
      throw Error(core::cat(
          {o.lda_model.string(), ": ", std::to_string(k.lda->num_words()),
           " words, but the documents have ", std::to_string(words),
           o.colour_words ? " (the vocabulary's and the colour words)" : " (the vocabulary's)"}));
    }
  } else {
    // The topic model learns from documents whose colour words count colour_weight times, and
    // records the weights, so that it reads every later document (the views', the held-out
    // views') weighted alike (LdaModel::word_weights); the words classifiers keep `corpus` as it
    // is, in k.training.
    const int weight = o.colour_words ? o.colour_weight : 1;
    const int first = static_cast<int>(k.vocabulary->size());
    l.timed("lda", [&] {
      if (weight == 1) {
        k.lda = views_lda(corpus, o.topics, o.seed);
      } else {
        std::vector<std::int32_t> weights = topics::weights_from(words, first, weight);
        k.lda = views_lda(topics::weighted_by(corpus, weights), o.topics, o.seed);
        k.lda->word_weights = std::move(weights);
      }
    });
  }
  topics::save_lda_model(*k.lda, o.out / "lda.model");
  k.training = corpus;
  // The ladder's pooled words classifier (ladder_pooled) reads the views' words beside theta.
  if (o.oracle_ladder && o.ladder_pooled) g.views.words = corpus;
  l.timed("model", [&] {
    g.views.theta = recognition::document_theta(*k.lda, corpus).theta;
    for (const auto& v : views) {
      g.views.labels.push_back(v.cls);
      g.views.push.push_back(v.push);
      g.views.tokens.push_back(v.descriptors.rows);
      ++g.views_per_class[static_cast<std::size_t>(v.cls)];
    }
    std::vector<int> remap(static_cast<std::size_t>(k.classes), -1);
    std::vector<std::string> names;
    for (int c = 0; c < k.classes; ++c) {
      if (g.views_per_class[static_cast<std::size_t>(c)] >= 2) {
        remap[static_cast<std::size_t>(c)] = static_cast<int>(names.size());
        names.push_back(g.class_names[static_cast<std::size_t>(c)]);
        g.model_class.push_back(c);
      } else {
        l.fault(c, "class-dropped", "fewer than 2 views: left out of the model");
      }
    }
    if (names.empty()) return;
    std::vector<int> labels;
    for (int lab : g.views.labels) labels.push_back(remap[static_cast<std::size_t>(lab)]);
    g.model = topics::fit_mot(g.views.theta, labels, names, o.mot).model;
    k.training_labels = labels;
  });
  if (g.model.num_classes() > 0) {
    const std::uint32_t vc = recognition::vocabulary_checksum(*k.vocabulary);
    topics::save_mot_model(g.model, topics::mot_basis(*k.lda, &vc), o.out / "model.mot");
  }
}

// The run's record as typed fields (options: the working ones, out the staging directory).
LearnResult finish(Core& k, const LearnOptions& o, const std::optional<SelfSupervisionScore>& score,
                   bool complete) {
  LearnResult r;
  r.score = score;
  r.options = o;
  r.complete = complete;
  const Learner& l = *k.learner;
  const Learning& g = k.learning;
  r.pushes = l.pushes();
  for (const auto& [reason, count] : l.skips()) r.skipped.push_back({reason, count});
  LearnSummary& s = r.summary;
  s.classes = k.classes;
  s.faults = l.faults();
  s.views = static_cast<int>(l.views().size());
  s.model_classes = g.model.num_classes();
  for (auto& p : r.pushes) {
    s.pushes_executed += p.executed ? 1 : 0;
    p.class_name = g.class_names[static_cast<std::size_t>(p.object)];
  }
  r.classes = g.class_names;
  for (int c = 0; c < k.classes; ++c) {
    const auto cu = static_cast<std::size_t>(c);
    LearnObjectRecord obj;
    obj.name = g.class_names[cu];
    for (const auto& p : r.pushes) obj.pushes += (p.object == c && p.executed) ? 1 : 0;
    obj.views = cu < g.views_per_class.size() ? g.views_per_class[cu] : 0;
    if (r.score) {
      obj.truth = r.score->class_object[cu];
      obj.purity = r.score->class_purity[cu];
    }
    r.objects.push_back(std::move(obj));
  }
  for (const auto& [stage, sec] : l.seconds()) {
    StageSeconds t{stage, sec, std::nullopt};
    if (const auto it = l.cpu_seconds().find(stage); it != l.cpu_seconds().end())
      t.cpu_seconds = it->second;
    r.timing.push_back(t);
  }
  if (k.vocabulary)
    r.vocabulary = LearnModelFile{"words", k.vocabulary->size(), "vocabulary.vocab"};
  if (k.lda) {
    r.topics = LearnModelFile{"count", k.lda->num_topics(), "lda.model"};
  }
  r.model_classes = g.model.names();
  r.dirichlet_likelihoods = l.dirichlet_measure();
  if (r.score) {
    s.mot_accuracy = r.score->mot_accuracy;
    s.argmax_accuracy = r.score->argmax_accuracy;
  }
  r.message = core::first_line(r.brief());
  return r;
}

// The record (document) of `r`, naming `out` as the run directory.
void record(LearnResult& r, const fs::path& out, const core::Provenance& provenance) {
  r.options.out = out;
  r.document = core::result_document(kLearnFormat, kFormatVersion, provenance);
  core::fields_into_json(r, r.document);
}

// learn.json (naming the final directory) into the staging directory `w.out`, then the commit.
void write_final(LearnResult& r, const LearnOptions& w, core::StagedDirectory& staged,
                 const core::Provenance& provenance) {
  record(r, staged.final_path(), provenance);
  core::write_json_atomic(w.out / "learn.json", r.document);
  if (r.complete) fs::remove(w.out / "INCOMPLETE");
  staged.commit();
}

}  // namespace

LearnWordScore score_by_words(const topics::MotModel& model, const topics::LdaModel& lda,
                              const topics::Corpus& training, const std::vector<int>& labels,
                              const std::vector<topics::Corpus>& held,
                              const std::vector<std::string>& objects,
                              const std::vector<std::string>& class_object, double weight,
                              bool per_view, int colour_from) {
  const int classes = model.num_classes();
  if (classes < 1) throw Error("score_by_words: the model has no classes");
  if (held.size() != objects.size()) {
    throw Error(core::cat({"score_by_words: ", std::to_string(held.size()),
                           " held-out corpora for ", std::to_string(objects.size()), " objects"}));
  }
  if (static_cast<int>(class_object.size()) != classes) {
    throw Error(core::cat({"score_by_words: ", std::to_string(class_object.size()),
                           " class names for ", std::to_string(classes), " classes"}));
  }
  if (!(weight >= 0 && weight <= 1)) {
    throw Error("score_by_words: weight " + std::to_string(weight) + " is not in [0, 1]");
  }
  // fit_word_multinomials checks labels against the documents and the classes.
  const Eigen::MatrixXd log_phi = topics::fit_word_multinomials(training, labels, classes, 1.0);
  // Every view alike (LearnOptions::mot_word_per_view): each view's counts scaled to the mean
  // view's number of words.
  const Eigen::MatrixXd log_phi_per_view =
      weighted_word_multinomials(training, labels, classes, per_view_weights(training, labels));
  // The colour words alone (colour_from >= 0; words_from refuses one past the documents' words):
  // each class's colour multinomial from its views weighed alike (a view with many features, often
  // one that took in a neighbour, no longer outweighs the rest; per_view_weights).
  const bool colour = colour_from >= 0;
  Eigen::MatrixXd log_colour;
  if (colour) log_colour = colour_multinomials(training, labels, classes, colour_from);
  int right_colour = 0;
  LearnWordScore s;
  s.weight = weight;
  s.per_view = per_view;
  s.word_weights.assign(std::begin(kLearnWordWeights), std::end(kLearnWordWeights));
  const std::size_t g_count = s.word_weights.size();
  s.grid.assign(g_count, 0.0);
  s.grid_per_view.assign(g_count, 0.0);
  int all = 0;
  int right_theta = 0;
  int right_words = 0;
  int right_pooled = 0;
  int right_pooled_per_view = 0;
  std::vector<int> right_grid(g_count, 0);
  std::vector<int> right_grid_per_view(g_count, 0);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    LearnWordObject ob;
    ob.name = objects[i];
    ob.grid.assign(g_count, 0.0);
    ob.grid_per_view.assign(g_count, 0.0);
    const topics::Corpus& docs = held[i];
    ob.held_out = static_cast<int>(docs.num_documents());
    if (ob.held_out > 0) {
      const auto right = [&](const topics::MotClassification& c) {
        int n = 0;
        for (int m : c.predicted)
          n += (m >= 0 && class_object[static_cast<std::size_t>(m)] == ob.name) ? 1 : 0;
        return n;
      };
      const Eigen::MatrixXd theta = recognition::document_theta(lda, docs).theta;
      const int rt = right(topics::classify_mot(model, theta));
      const topics::MotClassification by_words = topics::classify_mot_words(model, lda, docs);
      const int rw = right(by_words);
      const int rp = right(topics::pool_word_multinomials(model, by_words, log_phi, docs, weight));
      const int rv =
          right(topics::pool_word_multinomials(model, by_words, log_phi_per_view, docs, weight));
      for (std::size_t gi = 0; gi < g_count; ++gi) {
        const int rg = right(
            topics::pool_word_multinomials(model, by_words, log_phi, docs, s.word_weights[gi]));
        ob.grid[gi] = static_cast<double>(rg) / ob.held_out;
        right_grid[gi] += rg;
        const int rgv = right(topics::pool_word_multinomials(model, by_words, log_phi_per_view,
                                                             docs, s.word_weights[gi]));
        ob.grid_per_view[gi] = static_cast<double>(rgv) / ob.held_out;
        right_grid_per_view[gi] += rgv;
      }
      if (colour) {
        const int rc = right(classify_by_colour(model, log_colour, docs, colour_from));
        ob.colour = static_cast<double>(rc) / ob.held_out;
        right_colour += rc;
      }
      ob.theta = static_cast<double>(rt) / ob.held_out;
      ob.words = static_cast<double>(rw) / ob.held_out;
      ob.pooled = static_cast<double>(rp) / ob.held_out;
      ob.pooled_per_view = static_cast<double>(rv) / ob.held_out;
      all += ob.held_out;
      right_theta += rt;
      right_words += rw;
      right_pooled += rp;
      right_pooled_per_view += rv;
    }
    if (colour && !ob.colour) ob.colour = 0.0;
    s.objects.push_back(std::move(ob));
  }
  if (colour) s.colour = all > 0 ? static_cast<double>(right_colour) / all : 0.0;
  if (all > 0) {
    s.theta = static_cast<double>(right_theta) / all;
    s.words = static_cast<double>(right_words) / all;
    s.pooled = static_cast<double>(right_pooled) / all;
    s.pooled_per_view = static_cast<double>(right_pooled_per_view) / all;
    for (std::size_t gi = 0; gi < g_count; ++gi) {
      s.grid[gi] = static_cast<double>(right_grid[gi]) / all;
      s.grid_per_view[gi] = static_cast<double>(right_grid_per_view[gi]) / all;
    }
  }
  return s;
}

// LearnOptions::write_documents: the training views' and held-out views' documents, one a line
// in lda-c's "count word:count ..." form after a field or two saying whose it is.
namespace {

std::string documents_text(const topics::Corpus& training, const std::vector<int>& labels,
                           const std::vector<int>& pushes, const std::vector<ViewTruth>& truth,
                           const std::vector<std::string>& class_names,
                           const std::vector<std::string>& class_object,
                           const std::vector<topics::Corpus>& held,
                           const std::vector<std::string>& objects, int vocabulary_words) {
  const auto or_dash = [](const std::string& s) { return s.empty() ? std::string("-") : s; };
  const auto line = [](std::string& b, const topics::DocumentView& d) {
    b += std::to_string(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
      b += core::cat({" ", std::to_string(d.words[i]), ":", std::to_string(d.counts[i])});
    }
    b += '\n';
  };
  std::string b = "# proprio learn documents, version 1\n";
  b += core::cat({"words ", std::to_string(training.num_words()), " vocabulary ",
                  std::to_string(vocabulary_words), " classes ", std::to_string(class_names.size()),
                  "\n"});
  for (std::size_t c = 0; c < class_names.size(); ++c) {
    b += core::cat({"class ", std::to_string(c), " ", class_names[c], " ",
                    or_dash(c < class_object.size() ? class_object[c] : ""), "\n"});
  }
  for (std::size_t d = 0; d < training.num_documents(); ++d) {
    const ViewTruth* t = d < truth.size() ? &truth[d] : nullptr;
    b += core::cat({"view ", std::to_string(d < labels.size() ? labels[d] : -1), " ",
                    std::to_string(d < pushes.size() ? pushes[d] : -1), " ",
                    or_dash(t ? t->intended : ""), " ", or_dash(t ? t->object : ""), " "});
    line(b, training.document(d));
  }
  for (std::size_t i = 0; i < held.size() && i < objects.size(); ++i) {
    for (std::size_t d = 0; d < held[i].num_documents(); ++d) {
      b += core::cat({"held ", objects[i], " "});
      line(b, held[i].document(d));
    }
  }
  return b;
}

}  // namespace

std::optional<LearnHeadlineFigure> learn_headline(LearnHeadline headline,
                                                  const std::optional<SelfSupervisionScore>& score,
                                                  const std::optional<LearnWordScore>& words) {
  LearnHeadlineFigure h;
  // Both score types list their objects alike: a name, held-out views and an accuracy.
  const auto per_object = [&h](const auto& objects, auto accuracy_of) {
    for (const auto& o : objects) {
      h.names.push_back(o.name);
      h.held_out.push_back(o.held_out);
      h.per_object.push_back(accuracy_of(o));
    }
  };
  switch (headline) {
    case LearnHeadline::kMot:
    case LearnHeadline::kArgmax: {
      if (!score) return std::nullopt;
      const bool mot = headline == LearnHeadline::kMot;
      h.classifier = mot ? "mot" : "argmax";
      h.what = mot ? "Mixture of Topics" : "argmax theta";
      h.accuracy = mot ? score->mot_accuracy : score->argmax_accuracy;
      per_object(score->objects,
                 [mot](const ObjectScore& o) { return mot ? o.mot_accuracy : o.argmax_accuracy; });
      return h;
    }
    case LearnHeadline::kPooled: {
      if (!words) return std::nullopt;
      const bool per_view = words->per_view;
      h.classifier = per_view ? "pooled_per_view" : "pooled";
      h.what = core::printf_string("pooled words (weight %.2f, %s)", words->weight,
                                   per_view ? "per-view word multinomials" : "pooled counts");
      h.accuracy = per_view ? words->pooled_per_view : words->pooled;
      per_object(words->objects, [per_view](const LearnWordObject& o) {
        return per_view ? o.pooled_per_view : o.pooled;
      });
      return h;
    }
    case LearnHeadline::kAuto:  // resolved() replaces it before a run is scored
      return std::nullopt;
    case LearnHeadline::kColour: {
      if (!words || !words->colour) return std::nullopt;
      h.classifier = "colour";
      h.what = "colour words (per-view colour multinomials)";
      h.accuracy = *words->colour;
      per_object(words->objects, [](const LearnWordObject& o) { return o.colour.value_or(0.0); });
      return h;
    }
  }
  return std::nullopt;
}

std::string LearnResult::brief() const {
  const LearnSummary& s = summary;
  std::string b = core::printf_string(
      "learned %d of %d objects: %d pushes, %d views, %d faults logged, %.0f s", s.model_classes,
      s.classes, s.pushes_executed, s.views, s.faults, s.seconds);
  if (headline) {
    b += core::printf_string("\nheld-out accuracy (headline, %s): %.1f%% (", headline->what.c_str(),
                             100 * headline->accuracy);
    for (std::size_t i = 0; i < headline->names.size(); ++i) {
      b += core::printf_string("%s%s %.0f", i == 0 ? "" : ", ", headline->names[i].c_str(),
                               100 * headline->per_object[i]);
    }
    b += " %)";
  }
  if (score) {
    for (const ObjectScore& o : score->objects) {
      b += core::printf_string(
          "\n  %-12s held out %3d: Mixture of Topics %5.1f%%, argmax theta %5.1f%%", o.name.c_str(),
          o.held_out, 100 * o.mot_accuracy, 100 * o.argmax_accuracy);
    }
    b += core::printf_string("\nheld-out accuracy: Mixture of Topics %.1f%%, argmax theta %.1f%%",
                             100 * score->mot_accuracy, 100 * score->argmax_accuracy);
  }
  if (words) {
    b += core::printf_string(
        "\nheld out by words: Mixture of Topics by words %.1f%%, pooled with word multinomials "
        "(weight %.2f) %.1f%% (",
        100 * words->words, words->weight, 100 * words->pooled);
    for (std::size_t i = 0; i < words->objects.size(); ++i) {
      const LearnWordObject& ob = words->objects[i];
      b += core::printf_string("%s%s %.0f/%.0f", i == 0 ? "" : ", ", ob.name.c_str(),
                               100 * ob.words, 100 * ob.pooled);
    }
    b += core::printf_string(" %%)\n  with per-view word multinomials%s: pooled %.1f%% (",
                             words->per_view ? " (the pooled classifier)" : "",
                             100 * words->pooled_per_view);
    for (std::size_t i = 0; i < words->objects.size(); ++i) {
      const LearnWordObject& ob = words->objects[i];
      b += core::printf_string("%s%s %.0f", i == 0 ? "" : ", ", ob.name.c_str(),
                               100 * ob.pooled_per_view);
    }
    b += " %)";
    if (words->colour) {
      b += core::printf_string("\n  by the colour words alone: %.1f%% (", 100 * *words->colour);
      for (std::size_t i = 0; i < words->objects.size(); ++i) {
        const LearnWordObject& ob = words->objects[i];
        b += core::printf_string("%s%s %.0f", i == 0 ? "" : ", ", ob.name.c_str(),
                                 100 * ob.colour.value_or(0.0));
      }
      b += " %)";
    }
  }
  if (!coverage.empty()) {
    int covered = 0;
    b += "\ncoverage (turns that pushed it as the intended object):";
    for (const LearnCoverage& c : coverage) {
      b += core::printf_string(" %s %d,", c.name.c_str(), c.turns);
      covered += c.turns > 0 ? 1 : 0;
    }
    b += core::printf_string(" %d of %zu named objects covered", covered, coverage.size());
  }
  if (!skipped.empty()) {
    b += "\ncandidates skipped at the choices (why):";
    for (std::size_t i = 0; i < skipped.size(); ++i) {
      b += core::printf_string("%s %s %d", i == 0 ? "" : ",", skipped[i].reason.c_str(),
                               skipped[i].count);
    }
  }
  if (!report.empty()) b += "\nreport: " + report.string();
  return b;
}

LearnResult run_learn(const LearnOptions& options, robot::Robot& robot, TableAttendant& attendant,
                      int classes, const core::Provenance& provenance) {
  const auto t0 = Clock::now();
  const LearnOptions o = options.resolved();
  o.validate();
  if (classes < 1) throw Error("learn: at least one object is needed");
  LearnOptions w;
  const auto staged = prepare_out(o, w);
  Core k;
  k.classes = classes;
  learn_core(k, w, robot, attendant, provenance);
  LearnResult r = finish(k, w, std::nullopt, true);
  r.summary.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  write_final(r, w, *staged, provenance);
  return r;
}

SelfSupervisionOptions learn_score_options(const LearnOptions& o) {
  SelfSupervisionOptions so;
  so.objects = o.objects;
  so.seed = o.seed;
  so.width = o.width;
  so.height = o.height;
  so.held_out = o.held_out;
  so.features = o.features;
  so.dilate = o.dilate;
  so.min_features = o.min_features;
  so.mot = o.mot;
  so.colour_words = o.colour_words;
  so.colour = o.colour;
  so.oracle_ladder = o.oracle_ladder;
  so.pooled_score = o.oracle_ladder && o.ladder_pooled;
  return so;
}

sim::TableOptions learn_table(const LearnOptions& o) {
  sim::TableOptions table;
  table.objects = parse_object_list(o.objects);
  table.clutter = o.clutter;  // ground truth role "clutter": scattered, never learned or scored
  table.background = background_of(o);
  table.distractors = o.distractors;
  table.seed = o.seed;
  table.width = o.width;
  table.height = o.height;
  // Ground-truth masks (scoring only): the ladder's truth, and what each view in documents.txt
  // shows.
  table.record_masks = o.oracle_ladder || o.write_documents;
  table.depth = o.depth;  // an RGB-D camera: Look::depth for the planner
  return table;
}

LearnResult run_learn(const LearnOptions& options, const core::Provenance& provenance) {
  const auto t0 = Clock::now();
  const LearnOptions o = options.resolved();
  o.validate();
  const std::vector<std::string> objects = parse_object_list(o.objects);
  std::vector<std::string> all = objects;
  for (const auto& c : names_or_empty(o.clutter)) all.push_back(c);
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  for (const auto& name : all) (void)catalogue.get(name);  // Error: unknown object
  if (all.size() > kMaxObjects) {
    throw Error(core::cat({"learn: ", std::to_string(all.size()),
                           " objects do not fit on the table (at most ",
                           std::to_string(kMaxObjects), ")"}));
  }
  LearnOptions w;
  const auto staged = prepare_out(o, w);
  const sim::TableOptions table = learn_table(o);
  auto robot = std::make_unique<sim::SimulatedRobot>(table, catalogue);
  GroundTruthAttendant attendant(*robot, o.seed);
  Core k;
  // The robot is told how many objects lie on the table, not which are to be learned: with
  // learn_clutter it learns them all and the held-out views of the named objects score it.
  k.classes = static_cast<int>(o.learn_clutter ? all.size() : objects.size());
  learn_core(k, w, *robot, attendant, provenance);
  robot.reset();  // one GL context at a time: the held-out views need their own
  {
    LearnResult partial = finish(k, w, std::nullopt, false);
    record(partial, o.out, provenance);
    core::write_json_atomic(w.out / "learn.json", partial.document);
  }
  std::optional<SelfSupervisionScore> score;
  if (k.lda && k.vocabulary) {
    const auto th = Clock::now();
    score = score_self_supervision(k.learning, attendant, objects, *k.lda, *k.vocabulary,
                                   learn_score_options(o));
    k.learner->mutable_seconds()["held_out"] =
        std::chrono::duration<double>(Clock::now() - th).count();
  }
  std::optional<LearnWordScore> by_words;
  if (score && k.training && k.learning.model.num_classes() > 0) {
    const auto th = Clock::now();
    const std::vector<topics::Corpus> held = held_out_documents(o, objects, *k.vocabulary);
    std::vector<std::string> class_object;
    for (int c : k.learning.model_class)
      class_object.push_back(score->class_object[static_cast<std::size_t>(c)]);
    by_words = score_by_words(k.learning.model, *k.lda, *k.training, k.training_labels, held,
                              objects, class_object, o.mot_word_weight, o.mot_word_per_view,
                              o.colour_words ? static_cast<int>(k.vocabulary->size()) : -1);
    if (o.write_documents) {
      std::vector<std::string> names;
      for (int c : k.learning.model_class)
        names.push_back(k.learning.class_names[static_cast<std::size_t>(c)]);
      core::write_file_atomic(w.out / "documents.txt",
                              documents_text(*k.training, k.training_labels, k.learning.views.push,
                                             attendant.views(), names, class_object, held, objects,
                                             static_cast<int>(k.vocabulary->size())));
    }
    k.learner->mutable_seconds()["held_out_words"] =
        std::chrono::duration<double>(Clock::now() - th).count();
  }
  LearnResult r = finish(k, w, score, true);
  r.words = by_words;
  r.headline = learn_headline(o.headline, score, by_words);
  // Nothing to score (no score): no views were taken, so no vocabulary, LDA or object model was
  // made; the record says so.
  r.held_out = true;
  // What each push really moved (ground truth, scoring only): the attendant saw every push the
  // learner made, in the same order.
  const std::vector<PushTruth>& truth = attendant.pushes();
  for (std::size_t i = 0; i < r.pushes.size() && i < truth.size(); ++i) {
    const PushTruth& t = truth[i];
    r.pushes[i].truth =
        LearnPushTruth{t.intended, t.moved,
                       std::find(t.moved.begin(), t.moved.end(), t.intended) != t.moved.end() &&
                           !t.intended.empty(),
                       t.only_intended};
  }
  r.coverage = learn_coverage(objects, r.pushes);
  r.summary.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.record_seconds = true;
  write_final(r, w, *staged, provenance);
  LearnReportOptions page;
  page.dir = o.out;
  page.overwrite = true;  // in the run directory this run has just written
  r.report = write_learn_report(page, provenance).summary.page;
  return r;
}

}  // namespace proprio::loop
