#include "proprio/loop/push_run.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string_view>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/random.hpp"

namespace proprio::loop {
namespace fs = std::filesystem;

namespace {

constexpr const char* kPushFormat = "proprio.push";
constexpr const char* kEvaluationFormat = "proprio.push.evaluation";
constexpr int kFormatVersion = 1;
constexpr double kMs = 1000.0;
// core::stream_seed key of each table's choices (object, target), apart from its scene's stream.
constexpr std::uint64_t kTableStream = 0x7461626c65ULL;
// How much farther behind the object each retry after a refusal starts the push, and the most
// (PushPlanOptions' bound on approaches), m.
constexpr double kRetryApproach = 0.03;
constexpr double kMostApproach = 0.3;
// correction_gain: a push that moved the object less than this share of what it asked (or back)
// counts as this share.
constexpr double kLeastMovedShare = 1e-3;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The planner's table region: the table top; objects near the base axis are the arm.
planning::TableRegion region_of(const sim::SimulatedRobot& robot) {
  planning::TableRegion r;
  r.min = robot.table_min();
  r.max = robot.table_max();
  return r;
}

const sim::ObjectTruth* find_truth(const std::vector<sim::ObjectTruth>& t, const std::string& n) {
  for (const auto& o : t) {
    if (o.name == n) return &o;
  }
  return nullptr;
}

PushScore score(const std::vector<sim::ObjectTruth>& before,
                const std::vector<sim::ObjectTruth>& after, const std::string& intended,
                const Eigen::Vector2d& target, const std::vector<sim::ObjectId>& contacts) {
  PushScore s;
  s.intended = intended;
  for (std::size_t i = 0; i < before.size(); ++i) {
    // The distractors slide about by their script behind the work area: not the push's doing.
    if (before[i].role == sim::TableRole::kDistractor) continue;
    ObjectMove m;
    m.name = before[i].name;
    m.moved = (after[i].centre - before[i].centre).head<2>().norm();
    m.on_table = after[i].on_table;
    if (!m.on_table) ++s.off_table;
    const bool is_intended = m.name == intended;
    if (m.moved > kMovedThreshold) (is_intended ? s.moved_intended : s.moved_others) = true;
    if (is_intended) s.final_distance = (after[i].centre.head<2>() - target).norm();
    if (!is_intended &&
        std::find(contacts.begin(), contacts.end(), before[i].id) != contacts.end()) {
      s.touched_other = true;
    }
    s.objects.push_back(m);
  }
  s.only_intended = s.moved_intended && !s.moved_others;
  return s;
}

// Ground truth of one push: the other objects (not the intended one, not the distractors) it
// moved or the arm touched, with when the arm first touched each.
std::vector<OtherMove> others_of(const std::vector<sim::ObjectTruth>& before,
                                 const std::vector<sim::ObjectTruth>& after,
                                 const std::string& intended,
                                 const std::vector<sim::ArmContact>& contacts,
                                 const std::vector<sim::ObjectContact>& between) {
  const auto name_of = [&](sim::ObjectId id) {
    for (const sim::ObjectTruth& t : before) {
      if (t.id == id) return t.name;
    }
    return std::string("?");
  };
  std::vector<OtherMove> out;
  for (std::size_t i = 0; i < before.size() && i < after.size(); ++i) {
    if (before[i].role == sim::TableRole::kDistractor || before[i].name == intended) continue;
    OtherMove m;
    m.name = before[i].name;
    m.moved = (after[i].centre - before[i].centre).head<2>().norm();
    for (const sim::ArmContact& c : contacts) {
      if (c.id != before[i].id) continue;
      m.touch = core::choice_name(c.phase, sim::kContactPhaseNames);
      m.parts = c.parts;
    }
    for (const sim::ObjectContact& c : between) {
      std::vector<std::string>& list = c.already ? m.resting_on : m.hit_by;
      if (c.a == before[i].id) list.push_back(name_of(c.b));
      if (c.b == before[i].id) list.push_back(name_of(c.a));
    }
    if (m.moved > kMovedThreshold || !m.touch.empty()) out.push_back(m);
  }
  return out;
}

// Ground truth: the other objects (not `intended`, not distractors) under at least
// kMergedShare of `o`'s pixels in `mask`.
std::vector<std::string> merged_with(const planning::PutativeObject& o, const cv::Mat& mask,
                                     const std::vector<sim::ObjectTruth>& truth,
                                     const std::string& intended) {
  std::map<int, std::size_t> on;
  for (const auto& p : o.pixels) {
    const int u = static_cast<int>(std::lround(p.x()));
    const int v = static_cast<int>(std::lround(p.y()));
    if (u >= 0 && v >= 0 && u < mask.cols && v < mask.rows) ++on[mask.at<std::uint16_t>(v, u)];
  }
  std::vector<std::string> out;
  for (const sim::ObjectTruth& t : truth) {
    if (t.role == sim::TableRole::kDistractor || t.name == intended) continue;
    const auto it = on.find(static_cast<int>(t.id));
    if (it != on.end() &&
        static_cast<double>(it->second) >= kMergedShare * static_cast<double>(o.pixels.size())) {
      out.push_back(t.name);
    }
  }
  return out;
}

// Ground truth: `p` to the nearest footprint circle of an object other than `intended`, m.
double clearance_to_others(const std::vector<sim::ObjectTruth>& truth, const std::string& intended,
                           const Eigen::Vector2d& p) {
  double least = std::numeric_limits<double>::infinity();
  for (const sim::ObjectTruth& o : truth) {
    if (o.role == sim::TableRole::kDistractor || o.name == intended) continue;
    least = std::min(least, (o.centre.head<2>() - p).norm() - o.footprint_radius);
  }
  return std::isfinite(least) ? least : 0.0;
}

}  // namespace

void PushOptions::validate() const {
  core::check_field_bounds(*this, "push");
  table.validate();
  plan.validate();
}

std::string PushRunResult::brief() const {
  std::string s = std::string(core::choice_name(outcome, kPushOutcomeNames)) + ": " + message;
  if (score.final_distance >= 0) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "\n%s ended %.1f mm from the target after %d push%s; plan %.1f ms, look %.1f ms",
                  score.intended.c_str(), score.final_distance * kMs, pushes,
                  pushes == 1 ? "" : "es", plan.seconds * kMs, look_seconds * kMs);
    s += b;
  }
  return s;
}

double correction_gain(const Eigen::Vector2d& asked, const Eigen::Vector2d& moved, double min_gain,
                       double max_gain) {
  require(asked.allFinite() && moved.allFinite() && asked.norm() > 0,
          "correction gain: the push must have asked for a finite, non-zero move");
  require(min_gain > 0 && min_gain <= max_gain, "correction gain: need 0 < min_gain <= max_gain");
  const double k = moved.dot(asked) / asked.squaredNorm();  // share of the asked move made
  return std::clamp(1.0 / std::max(k, kLeastMovedShare), min_gain, max_gain);
}

int putative_object_on(const planning::PlanningView& view, const cv::Mat& mask, int id) {
  int best = -1;
  std::size_t best_count = 0;
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    const auto& o = view.objects[k];
    std::size_t on = 0;
    for (const auto& p : o.pixels) {
      const int u = static_cast<int>(std::lround(p.x()));
      const int v = static_cast<int>(std::lround(p.y()));
      if (u >= 0 && v >= 0 && u < mask.cols && v < mask.rows &&
          mask.at<std::uint16_t>(v, u) == id) {
        ++on;
      }
    }
    if (2 * on >= o.pixels.size() && on > best_count) {
      best_count = on;
      best = static_cast<int>(k);
    }
  }
  return best;
}

namespace {

cv::Point pixel(const geometry::Camera& cam, const Eigen::Vector2d& p, double height) {
  const Eigen::Vector2d px = cam.project(Eigen::Vector3d(p.x(), p.y(), height));
  return {static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y()))};
}

// The look with the putative objects (boxes, hulls, centres) and the plan (path red, target
// green) drawn on it.
cv::Mat draw_plan(const robot::Look& look, const planning::PlanningView& view,
                  const planning::PushPlan& plan, const sim::ObjectTruth* truth) {
  cv::Mat img = look.image.clone();
  const cv::Scalar cyan(255, 255, 0);
  for (const auto& o : view.objects) {
    cv::rectangle(img, o.box, cyan, 1);
    std::vector<cv::Point> hull;
    for (const auto& h : o.hull_pixels) {
      hull.emplace_back(static_cast<int>(std::lround(h.x())), static_cast<int>(std::lround(h.y())));
    }
    cv::polylines(img, hull, true, cyan, 1);
    cv::circle(img, pixel(look.camera, o.centre, 0.0), 3, cyan, -1);
  }
  for (const auto& f : view.features) cv::circle(img, f.pt, 1, cv::Scalar(0, 200, 255), -1);
  if (truth != nullptr) {  // ground truth, magenta: where the object's centre really is
    cv::drawMarker(img, pixel(look.camera, truth->centre.head<2>(), 0.0), cv::Scalar(255, 0, 255),
                   cv::MARKER_CROSS, 12, 2);
  }
  if (plan.outcome == planning::PlanOutcome::kPlanned) {
    cv::arrowedLine(img, pixel(look.camera, plan.push.start, plan.push.height),
                    pixel(look.camera, plan.push.end, plan.push.height), cv::Scalar(0, 0, 255), 2);
    cv::circle(img, pixel(look.camera, plan.target, 0.0), 5, cv::Scalar(0, 255, 0), -1);
  }
  return img;
}

}  // namespace

namespace {

std::string episode_name(int k) {
  if (k == 0) return "episode";
  std::string s = "episode_";
  s += std::to_string(k + 1);
  return s;
}

// Where a run writes its files: options.out itself, or the staging directory that run_push swaps
// in whole at the end (then the record names options.out from the start).
struct WorkDirectory {
  fs::path dir;            ///< empty: no files
  bool overwrite = false;  ///< episodes may replace what is there
};

PushRunResult push_in(sim::SimulatedRobot& robot, const PushOptions& options,
                      const WorkDirectory& work, const core::Provenance& provenance) {
  options.validate();
  PushRunResult r;
  r.options = options;
  const auto t_look = std::chrono::steady_clock::now();
  const robot::Look look = robot.look();
  const planning::TableRegion region = region_of(robot);
  const planning::PlanningView view = planning::look_for_objects(look, region, options.plan);
  r.look_seconds = seconds_since(t_look);
  const std::vector<sim::ObjectTruth> before = robot.ground_truth();

  int object = options.blob;
  std::string intended;
  if (!options.object.empty()) {
    const sim::ObjectTruth* t = find_truth(before, options.object);
    if (t == nullptr) {
      std::string known;
      for (const auto& o : before) known += (known.empty() ? "" : ", ") + o.name;
      throw Error("unknown object '" + options.object + "' (on the table: " + known + ")");
    }
    intended = t->name;
    object = putative_object_on(view, robot.ground_truth_mask(), t->id);
    if (object < 0) {
      r.outcome = PushOutcome::kObjectNotSeen;
      r.message = "no putative object lies on the " + intended + " (" +
                  std::to_string(view.objects.size()) + " in view)";
    }
  }
  const Eigen::Vector2d target(options.target_x, options.target_y);
  if (r.outcome != PushOutcome::kObjectNotSeen) {
    // The closed loop: look (the first look above), plan, push, look again and find the object.
    robot::Look cur_look = look;
    planning::PlanningView cur_view = view;
    int cur_object = object;
    std::vector<sim::ObjectId> contacts;
    const int budget = options.goal == planning::PushGoal::kTarget ? options.max_pushes : 1;
    // The loop's gain: how much farther than needed a correction asks the object to go, from
    // how far the last push moved it against what it asked (an undershooting push, e.g. a
    // pusher that meets the object later than its hull said, is made up for next time; with
    // min_gain < 1 an overshooting one, an object that slid or rolled on, asks less next time).
    double gain = 1.0;
    for (int k = 0; k < budget; ++k) {
      PushStep step;
      const Eigen::Vector2d c = cur_view.objects[static_cast<std::size_t>(cur_object)].centre;
      const Eigen::Vector2d aim = c + gain * (target - c);
      for (int attempt = 0; attempt <= options.retries; ++attempt) {
        robot::ArmState arm(robot.arm());
        planning::PushPlanOptions popt = options.plan;
        // The descent pose check poses the hand as the table's robot rolls it.
        popt.roll_across = options.table.roll_across;
        popt.seed = core::stream_seed(options.plan.seed, static_cast<std::uint64_t>(k),
                                      static_cast<std::uint64_t>(attempt));
        // A refusal is a hand that would come down on or beside a tall object near the start:
        // each retry starts farther behind the object.
        popt.min_approach = std::min(kMostApproach, popt.min_approach + attempt * kRetryApproach);
        popt.max_approach = std::min(kMostApproach, popt.max_approach + attempt * kRetryApproach);
        // refusal_pose_margin: a retry after a refusal takes the least-cost path whose arm keeps
        // clear on its way down (its own kinematics against the depth image), when there is one.
        if (attempt > 0) popt = planning::after_refusal(popt);
        // A push round a blocked line needs a push after it to reach the target.
        if (k + 1 >= budget) {
          popt.via_points = 0;
          popt.via_blocked = 0;
        }
        // correction_hand_margin: a correction is planned with the hand kept clear.
        const bool hand_checked = k > 0 && popt.correction_hand_margin > 0;
        if (hand_checked)
          popt.hand_margin = std::max(popt.hand_margin, popt.correction_hand_margin);
        // first_hand_margin: the first push is planned with its hand kept clear where it can be
        // (a waypoint only when a push follows to go on to the target).
        const double first_hand =
            k == 0 && options.goal == planning::PushGoal::kTarget ? popt.first_hand_margin : 0.0;
        const int first_via = k + 1 < budget ? planning::kFirstHandVia : 0;
        const auto plan_to = [&](const Eigen::Vector2d& goal_point) {
          return planning::plan_push_hand_clear(cur_view, cur_object, options.goal, goal_point,
                                                region, arm, robot.joints(), popt, first_hand,
                                                first_via);
        };
        planning::PushPlan plan = plan_to(aim);
        if (plan.outcome != planning::PlanOutcome::kPlanned && gain != 1.0) plan = plan_to(target);
        if (plan.outcome != planning::PlanOutcome::kPlanned && attempt > 0) {
          // The longer approach out of reach: another path of the usual approach, as before.
          popt.min_approach = options.plan.min_approach;
          popt.max_approach = options.plan.max_approach;
          plan = plan_to(aim);
        }
        // A retry that cannot be planned leaves the refusal as the step's outcome.
        if (plan.outcome != planning::PlanOutcome::kPlanned && attempt > 0) break;
        step.plan = std::move(plan);
        if (step.plan.outcome != planning::PlanOutcome::kPlanned) break;
        if (hand_checked && step.plan.hand_blocked > 0) {
          // The correction's hand would meet another object: not made, the loop ends here.
          step.message =
              "correction not made: the hand would come " +
              std::to_string(static_cast<int>(std::lround(step.plan.hand_blocked * 1000))) +
              " mm too near another object (correction_hand_margin)";
          spdlog::info("push {}: {}", k + 1, step.message);
          break;
        }
        robot::PushRecording rec;
        if (!work.dir.empty()) rec.episode_dir = work.dir / episode_name(k);
        rec.fps = options.fps;
        rec.overwrite = work.overwrite;
        rec.run = provenance;
        try {
          const std::vector<sim::ObjectTruth> truth_before = robot.ground_truth();
          step.start_clearance = clearance_to_others(truth_before, intended, step.plan.push.start);
          step.merged = merged_with(cur_view.objects[static_cast<std::size_t>(cur_object)],
                                    robot.ground_truth_mask(), truth_before, intended);
          step.report = robot.push(step.plan.push, rec);
          step.others =
              others_of(truth_before, robot.ground_truth(), intended,
                        robot.last_push_contact_phases(), robot.last_push_object_contacts());
          step.message = step.report->message;
          // The record names the episode where it ends up (run_push swaps the staging in).
          if (!work.dir.empty()) step.report->episode_dir = options.out / episode_name(k);
          break;
        } catch (const Error& e) {
          // The robot refused (nothing moved): another sampled path, when retries are left.
          step.message = e.what();
          spdlog::info("push {}: refused ({}), attempt {} of {}", k + 1, e.what(), attempt + 1,
                       options.retries + 1);
        }
      }
      if (k == 0) {
        r.plan = step.plan;
        if (intended.empty() && r.plan.outcome == planning::PlanOutcome::kPlanned) {
          const cv::Mat mask = robot.ground_truth_mask();
          for (const auto& o : before) {
            if (putative_object_on(view, mask, o.id) == object) intended = o.name;
          }
        }
      }
      if (step.plan.outcome != planning::PlanOutcome::kPlanned) {
        step.message = step.plan.message;
        if (k == 0) {
          r.outcome = PushOutcome::kNotPlanned;
          r.message = step.plan.message;
        }
        r.steps.push_back(std::move(step));
        break;
      }
      if (!step.report) {
        if (k == 0) {
          r.outcome = PushOutcome::kRobotRefused;
          r.message = step.message;
        }
        r.steps.push_back(std::move(step));
        break;
      }
      ++r.pushes;
      if (k == 0) r.report = step.report;
      for (const sim::ObjectId id : robot.last_push_contacts()) contacts.push_back(id);
      const std::vector<sim::ObjectTruth> now = robot.ground_truth();
      if (const sim::ObjectTruth* t = find_truth(now, intended)) {
        step.true_distance = (t->centre.head<2>() - target).norm();
        if (options.goal != planning::PushGoal::kTarget) {
          step.true_distance = (t->centre.head<2>() - step.plan.target).norm();
        }
      }
      if (k + 1 < budget) {
        // Look again and find the pushed object from the images alone.
        const auto t1 = std::chrono::steady_clock::now();
        robot::Look next_look = robot.look();
        planning::PlanningView next_view =
            planning::look_for_objects(next_look, region, options.plan);
        const Eigen::Vector2d asked = step.plan.target - c;
        const Eigen::Vector2d expected = c + asked / gain;  // where the loop wants it
        const int found =
            planning::find_pushed_object(cur_look.image, next_look.image, next_view,
                                         cur_view.objects[static_cast<std::size_t>(cur_object)],
                                         expected, options.track_radius, region, options.plan);
        step.look_seconds = seconds_since(t1);
        if (found >= 0) {
          const planning::PutativeObject& o = next_view.objects[static_cast<std::size_t>(found)];
          step.seen_centre = o.centre;
          step.seen_distance = (o.centre - target).norm();
          if (const sim::ObjectTruth* t = find_truth(now, intended)) {
            step.tracked_on_object =
                putative_object_on(next_view, robot.ground_truth_mask(), t->id) == found;
          }
        }
        if (found >= 0 && asked.norm() > 1e-6) {
          gain = correction_gain(asked, step.seen_centre - c, options.min_gain, options.max_gain);
        }
        // A shortened push stopped where the way on meets another object: the next would too.
        const bool done =
            found < 0 || step.seen_distance <= options.tolerance || step.plan.shortened > 0;
        if (found < 0) step.message += "; the pushed object was not found again";
        if (!work.dir.empty()) {  // the look after push k: out/look_2.png, ...
          std::string name = "look_";
          name += std::to_string(k + 2);
          name += ".png";
          planning::PushPlan none;
          cv::imwrite((work.dir / name).string(),
                      draw_plan(next_look, next_view, none, find_truth(now, intended)));
        }
        r.steps.push_back(std::move(step));
        if (done) break;
        cur_look = std::move(next_look);
        cur_view = std::move(next_view);
        cur_object = found;
      } else {
        r.steps.push_back(std::move(step));
      }
    }
    if (r.pushes > 0) {
      std::sort(contacts.begin(), contacts.end());
      const Eigen::Vector2d goal_point =
          options.goal == planning::PushGoal::kTarget ? target : r.plan.target;
      r.score = score(before, robot.ground_truth(), intended, goal_point, contacts);
      if (const sim::ObjectTruth* t = find_truth(before, intended)) {
        r.score.centre_error = (t->centre.head<2>() - r.plan.centre).norm();
      }
      if (!r.score.moved_intended && !r.score.moved_others) {
        r.outcome = PushOutcome::kMovedNothing;
        r.message = "the push moved nothing";
      } else if (!r.score.moved_intended && !intended.empty()) {
        r.outcome = PushOutcome::kMovedWrong;
        r.message = "the push moved another object, not the " + intended;
      } else {
        r.outcome = PushOutcome::kPushed;
        r.message = r.plan.message;
        if (r.pushes > 1) {
          r.message += " (then ";
          r.message += std::to_string(r.pushes - 1);
          r.message += r.pushes == 2 ? " more push)" : " more pushes)";
        }
      }
    }
  }
  if (r.outcome != PushOutcome::kPushed) spdlog::warn("push: {}", r.message);
  if (!work.dir.empty()) {
    cv::imwrite((work.dir / "plan.png").string(),
                draw_plan(look, view, r.plan, find_truth(before, intended)));
  }

  r.putative_objects = putative_object_records(view, true);
  r.document = core::result_document(kPushFormat, kFormatVersion, provenance);
  core::fields_into_json(r, r.document);
  return r;
}

}  // namespace

PushRunResult push_once(sim::SimulatedRobot& robot, const PushOptions& options,
                        const core::Provenance& provenance) {
  return push_in(robot, options, {options.out, options.overwrite}, provenance);
}

namespace {

// What marks a directory proprio push wrote: a finished run, or one stopped after its first push.
constexpr std::string_view kPushMarkers[] = {"push.json", "episode/episode.json"};

}  // namespace

PushRunResult run_push(const PushOptions& options, const core::Provenance& provenance) {
  options.validate();
  // Written under a hidden name beside --out and swapped in whole at the end (issue 16): an
  // older push's files this one does not write go, and a failed or killed run leaves the old.
  std::optional<core::StagedDirectory> staged;
  WorkDirectory work{{}, true};  // the directory was checked here
  PushOptions named = options;   // as the record names them: out is the final directory
  if (!options.out.empty()) {
    if (fs::exists(options.out) && !options.overwrite) {
      throw Error(options.out.string() + ": already exists (use --overwrite to replace it)");
    }
    staged.emplace(options.out, options.overwrite, kPushMarkers);
    work.dir = staged->staging_path();
    named.out = staged->final_path();
  }
  sim::SimulatedRobot robot(options.table, sim::ObjectCatalogue::load_default());
  if (!work.dir.empty()) cv::imwrite((work.dir / "before.png").string(), robot.look().image);
  PushRunResult r = push_in(robot, named, work, provenance);
  if (staged) {
    cv::imwrite((work.dir / "after.png").string(), robot.look().image);
    core::write_json_atomic(work.dir / "push.json", r.document);
    staged->commit();
  }
  return r;
}

void PushEvaluationOptions::validate() const {
  core::check_field_bounds(*this, "push evaluation");
  require(min_objects <= max_objects, "push evaluation: min_objects must be <= max_objects");
  require(min_shift <= max_shift, "push evaluation: min_shift must be <= max_shift");
  require(max_objects + clutter <= 8, "push evaluation: at most 8 objects and clutter together");
  plan.validate();
}

namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace

std::string PushEvaluationResult::brief() const {
  char b[768];
  std::snprintf(
      b, sizeof b,
      "%d tables: %d pushed, %d not planned, %d object not seen, %d refused by the robot\n"
      "final distance to target: median %.1f mm, 90th pct %.1f mm (centre estimate off by "
      "%.1f mm, median)\n"
      "moved the intended object and only it: %.0f%%; arm touched another: %.0f%%; "
      "objects off the table: %d\n"
      "plan time: median %.2f ms, max %.2f ms; look %.1f ms\n"
      "pushes per table %.2f (closed loop); after the first push alone: median %.1f mm; "
      "object found again on the right object: %.0f%%",
      tables, planned, not_planned, not_seen, refused, median_distance * kMs, p90_distance * kMs,
      median_centre_error * kMs, 100 * only_intended_rate, 100 * touched_other_rate, off_table,
      median_plan_ms, max_plan_ms, median_look_ms, mean_pushes, median_first_distance * kMs,
      100 * tracked_rate);
  return b;
}

PushTarget draw_push_target(const sim::BoxFootprint& object,
                            const std::vector<sim::BoxFootprint>& others,
                            const PushEvaluationOptions& options, core::Rng& rng) {
  options.validate();
  const sim::ScatterRegion scatter;
  const bool clearance = options.target_clearance > 0;
  const int most = clearance ? kClearTargetDraws : 100;
  PushTarget out;
  out.point = object.centre;
  std::optional<Eigen::Vector2d> first;  // the first draw in the region
  for (int k = 0; k < most; ++k) {
    const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
    const double d = rng.uniform(options.min_shift, options.max_shift);
    const Eigen::Vector2d c = object.centre + d * Eigen::Vector2d(std::cos(a), std::sin(a));
    out.draws = k + 1;
    if (c.x() < scatter.min.x() || c.x() > scatter.max.x() || c.y() < scatter.min.y() ||
        c.y() > scatter.max.y() || c.norm() < scatter.base_clearance) {
      continue;
    }
    if (!first) first = c;
    if (!clearance) break;
    sim::BoxFootprint there = object;
    there.centre = c;
    const bool clear = std::all_of(others.begin(), others.end(), [&](const sim::BoxFootprint& o) {
      return sim::footprint_overlap(there, o, options.target_clearance) == 0.0;
    });
    if (clear) {
      out.point = c;
      return out;
    }
  }
  if (first) out.point = *first;
  out.clear = !clearance;
  return out;
}

PushEvaluationResult run_push_evaluation(const PushEvaluationOptions& options,
                                         const core::Provenance& provenance) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  PushEvaluationResult r;
  r.options = options;
  std::vector<double> distances;
  std::vector<double> centre_errors;
  std::vector<double> plan_ms;
  std::vector<double> look_ms;
  std::vector<double> first_distances;
  int only = 0;
  int touched = 0;
  int pushes_made = 0;
  int looks_after = 0;
  int tracked = 0;
  for (int t = 0; t < options.tables; ++t) {
    const std::uint64_t seed = options.seed + static_cast<std::uint64_t>(t);
    auto rng = core::Rng::stream(seed, kTableStream);
    sim::TableOptions table;
    table.seed = seed;
    const int spread = options.max_objects - options.min_objects + 1;
    table.object_count =
        options.min_objects + static_cast<int>(rng.index(static_cast<std::uint64_t>(spread)));
    table.width = options.width;
    table.height = options.height;
    table.background = options.background;
    table.distractors = options.distractors;
    if (options.clutter > 0) table.clutter = std::to_string(options.clutter);
    table.depth = options.depth;
    table.roll_across = options.roll_across;
    sim::SimulatedRobot robot(table, catalogue);
    // The object to push: one of the table's objects (not the clutter, not a distractor).
    std::vector<sim::ObjectTruth> truth = robot.ground_truth();
    std::erase_if(truth,
                  [](const sim::ObjectTruth& o) { return o.role != sim::TableRole::kObject; });
    const sim::ObjectTruth chosen = truth[rng.index(truth.size())];
    // A target min..max_shift away, inside the scatter region (with target_clearance: where the
    // object fits beside the other objects and the clutter).
    std::vector<sim::BoxFootprint> others;
    for (const sim::ObjectTruth& o : robot.ground_truth()) {
      if (o.id != chosen.id && o.role != sim::TableRole::kDistractor) {
        others.push_back(sim::box_footprint(o, catalogue.get(o.name)));
      }
    }
    const PushTarget drawn = draw_push_target(
        sim::box_footprint(chosen, catalogue.get(chosen.name)), others, options, rng);
    const Eigen::Vector2d target = drawn.point;
    if (options.target_clearance > 0) {
      spdlog::info("table {}: target ({:.3f}, {:.3f}) for the {} after {} draws, {}", seed,
                   target.x(), target.y(), chosen.name, drawn.draws,
                   drawn.clear ? "clear" : "none clear: the first in the region kept");
    }
    PushOptions po;
    po.table = table;
    po.plan = options.plan;
    po.plan.seed = seed;
    po.object = chosen.name;
    po.target_x = target.x();
    po.target_y = target.y();
    po.max_pushes = options.max_pushes;
    po.tolerance = options.tolerance;
    po.max_gain = options.max_gain;
    po.min_gain = options.min_gain;
    po.retries = options.retries;
    PushRunResult p;
    try {
      p = push_once(robot, po, provenance);
    } catch (const Error& e) {
      // A physics warning or an unreachable motion after planning: logged, counted as not planned.
      spdlog::warn("table {}: {}", seed, e.what());
      p.outcome = PushOutcome::kNotPlanned;
      p.message = e.what();
    }
    ++r.tables;
    if (p.outcome == PushOutcome::kObjectNotSeen) ++r.not_seen;
    if (p.outcome == PushOutcome::kNotPlanned) ++r.not_planned;
    if (p.outcome == PushOutcome::kRobotRefused) ++r.refused;
    if (p.report) {
      ++r.planned;
      distances.push_back(p.score.final_distance);
      if (p.score.centre_error >= 0) centre_errors.push_back(p.score.centre_error);
      only += p.score.only_intended ? 1 : 0;
      touched += p.score.touched_other ? 1 : 0;
      r.off_table += p.score.off_table;
      plan_ms.push_back(p.plan.seconds * kMs);
      pushes_made += p.pushes;
      if (!p.steps.empty() && p.steps.front().true_distance >= 0) {
        first_distances.push_back(p.steps.front().true_distance);
      }
      for (const PushStep& s : p.steps) {
        if (s.look_seconds > 0) {
          ++looks_after;
          tracked += s.tracked_on_object ? 1 : 0;
        }
      }
    }
    look_ms.push_back(p.look_seconds * kMs);
    PushEvaluationTable row;
    row.seed = seed;
    row.objects = table.object_count;
    row.clutter = options.clutter;
    row.object = chosen.name;
    row.target = target;
    row.outcome = p.outcome;
    row.message = p.message;
    row.executed = p.report.has_value();
    row.final_distance = p.score.final_distance;
    row.centre_error = p.score.centre_error;
    row.only_intended = p.score.only_intended;
    row.touched_other = p.score.touched_other;
    row.off_table = p.score.off_table;
    row.plan_ms = p.plan.seconds * kMs;
    row.pushes = p.pushes;
    if (options.target_clearance > 0) {
      row.target_draws = drawn.draws;
      row.target_clear = drawn.clear;
    }
    for (const PushStep& s : p.steps) {
      PushEvaluationStep e;
      e.true_distance = s.true_distance;
      e.seen_distance = s.seen_distance;
      e.tracked_on_object = s.tracked_on_object;
      e.plan = s.plan.outcome;
      e.executed = s.report.has_value();
      e.message = s.message;
      e.others = s.others;
      e.start_clearance = s.start_clearance;
      e.start = s.plan.push.start;
      e.end = s.plan.push.end;
      e.blocked = s.plan.blocked;
      e.via = s.plan.via;
      e.shortened = s.plan.shortened;
      e.descent_met = s.plan.descent_met;
      e.target_moved = s.plan.target_moved;
      e.hand_cleared = s.plan.hand_cleared;
      e.hand_fallback = s.plan.hand_fallback;
      e.merged = s.merged;
      e.jaws = s.plan.push.jaws;
      row.steps.push_back(std::move(e));
    }
    r.pushes.push_back(std::move(row));
  }
  r.median_distance = percentile(distances, 0.5);
  r.p90_distance = percentile(distances, 0.9);
  r.median_centre_error = percentile(centre_errors, 0.5);
  r.only_intended_rate = r.planned > 0 ? static_cast<double>(only) / r.planned : 0.0;
  r.touched_other_rate = r.planned > 0 ? static_cast<double>(touched) / r.planned : 0.0;
  r.median_plan_ms = std::max(0.0, percentile(plan_ms, 0.5));
  r.max_plan_ms = plan_ms.empty() ? 0.0 : *std::max_element(plan_ms.begin(), plan_ms.end());
  r.median_look_ms = std::max(0.0, percentile(look_ms, 0.5));
  r.median_first_distance = percentile(first_distances, 0.5);
  r.mean_pushes = r.planned > 0 ? static_cast<double>(pushes_made) / r.planned : 0.0;
  r.tracked_rate = looks_after > 0 ? static_cast<double>(tracked) / looks_after : 0.0;
  r.seconds = seconds_since(t0);
  r.document = core::result_document(kEvaluationFormat, kFormatVersion, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace proprio::loop
