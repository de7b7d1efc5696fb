#include "proprio/loop/push_run.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

core::Json xy(const Eigen::Vector2d& p) { return core::Json::array({p.x(), p.y()}); }

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

core::Json score_json(const PushScore& s) {
  core::Json j;
  j["intended"] = s.intended;
  j["final_distance"] = s.final_distance >= 0 ? core::Json(s.final_distance) : core::Json();
  j["centre_error"] = s.centre_error >= 0 ? core::Json(s.centre_error) : core::Json();
  j["moved_intended"] = s.moved_intended;
  j["moved_others"] = s.moved_others;
  j["only_intended"] = s.only_intended;
  j["touched_other"] = s.touched_other;
  j["off_table"] = s.off_table;
  core::Json objects = core::Json::array();
  for (const ObjectMove& m : s.objects) {
    objects.push_back({{"name", m.name}, {"moved", m.moved}, {"on_table", m.on_table}});
  }
  j["objects"] = objects;
  return j;
}

core::Json plan_json(const planning::PushPlan& p) {
  core::Json j;
  j["outcome"] = std::string(core::choice_name(p.outcome, planning::kPlanOutcomeNames));
  j["message"] = p.message;
  j["object"] = p.object;
  j["seconds"] = p.seconds;
  j["sampled"] = p.sampled;
  j["rejected_region"] = p.rejected_region;
  j["rejected_reach"] = p.rejected_reach;
  if (p.outcome == planning::PlanOutcome::kPlanned) {
    j["centre"] = xy(p.centre);
    j["target"] = xy(p.target);
    j["start"] = xy(p.push.start);
    j["end"] = xy(p.push.end);
    j["edge_distance"] = p.edge_distance;
    j["approach"] = p.approach;
    j["cost"] = p.cost;
  }
  return j;
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

core::Json step_json(const PushStep& s) {
  core::Json j;
  j["plan"] = plan_json(s.plan);
  j["message"] = s.message;
  j["executed"] = s.report.has_value();
  j["touched"] = s.report ? s.report->touched : false;
  j["episode"] = s.report ? s.report->episode_dir.string() : std::string();
  j["seen_centre"] = s.seen_distance >= 0 ? xy(s.seen_centre) : core::Json();
  j["seen_distance"] = s.seen_distance >= 0 ? core::Json(s.seen_distance) : core::Json();
  j["true_distance"] = s.true_distance >= 0 ? core::Json(s.true_distance) : core::Json();
  j["tracked_on_object"] = s.tracked_on_object;
  j["look_seconds"] = s.look_seconds;
  return j;
}

}  // namespace

PushRunResult push_once(sim::SimulatedRobot& robot, const PushOptions& options,
                        const core::Provenance& provenance) {
  options.validate();
  PushRunResult r;
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
    // pusher that meets the object later than its hull said, is made up for next time).
    double gain = 1.0;
    for (int k = 0; k < budget; ++k) {
      PushStep step;
      const Eigen::Vector2d c = cur_view.objects[static_cast<std::size_t>(cur_object)].centre;
      const Eigen::Vector2d aim = c + gain * (target - c);
      for (int attempt = 0; attempt <= options.retries; ++attempt) {
        robot::ArmState arm(robot.arm());
        planning::PushPlanOptions popt = options.plan;
        popt.seed = core::stream_seed(options.plan.seed, static_cast<std::uint64_t>(k),
                                      static_cast<std::uint64_t>(attempt));
        // A refusal is a hand that would come down on or beside a tall object near the start:
        // each retry starts farther behind the object.
        popt.min_approach = std::min(kMostApproach, popt.min_approach + attempt * kRetryApproach);
        popt.max_approach = std::min(kMostApproach, popt.max_approach + attempt * kRetryApproach);
        planning::PushPlan plan = planning::plan_push(cur_view, cur_object, options.goal, aim,
                                                      region, arm, robot.joints(), popt);
        if (plan.outcome != planning::PlanOutcome::kPlanned && gain > 1.0) {
          plan = planning::plan_push(cur_view, cur_object, options.goal, target, region, arm,
                                     robot.joints(), popt);
        }
        if (plan.outcome != planning::PlanOutcome::kPlanned && attempt > 0) {
          // The longer approach out of reach: another path of the usual approach, as before.
          popt.min_approach = options.plan.min_approach;
          popt.max_approach = options.plan.max_approach;
          plan = planning::plan_push(cur_view, cur_object, options.goal, aim, region, arm,
                                     robot.joints(), popt);
        }
        // A retry that cannot be planned leaves the refusal as the step's outcome.
        if (plan.outcome != planning::PlanOutcome::kPlanned && attempt > 0) break;
        step.plan = std::move(plan);
        if (step.plan.outcome != planning::PlanOutcome::kPlanned) break;
        robot::PushRecording rec;
        if (!options.out.empty()) rec.episode_dir = options.out / episode_name(k);
        rec.fps = options.fps;
        rec.overwrite = options.overwrite;
        rec.run = provenance;
        try {
          step.report = robot.push(step.plan.push, rec);
          step.message = step.report->message;
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
          const double moved = (step.seen_centre - c).dot(asked) / asked.squaredNorm();
          gain = std::clamp(1.0 / std::max(moved, 1e-3), 1.0, options.max_gain);
        }
        const bool done = found < 0 || step.seen_distance <= options.tolerance;
        if (found < 0) step.message += "; the pushed object was not found again";
        if (!options.out.empty()) {  // the look after push k: out/look_2.png, ...
          std::string name = "look_";
          name += std::to_string(k + 2);
          name += ".png";
          planning::PushPlan none;
          cv::imwrite((options.out / name).string(),
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
  if (!options.out.empty()) {
    cv::imwrite((options.out / "plan.png").string(),
                draw_plan(look, view, r.plan, find_truth(before, intended)));
  }

  core::Json& d = r.document;
  d = core::result_document(kPushFormat, kFormatVersion, provenance);
  d["outcome"] = std::string(core::choice_name(r.outcome, kPushOutcomeNames));
  d["message"] = r.message;
  d["options"] = core::fields_to_json(options);
  d["table"] = core::fields_to_json(options.table);
  d["planner"] = core::fields_to_json(options.plan);
  core::Json objects = core::Json::array();
  for (const auto& o : view.objects) {
    objects.push_back({{"centre", xy(o.centre)},
                       {"centre_pixel", xy(o.centre_pixel)},
                       {"features", static_cast<int>(o.pixels.size())},
                       {"box", core::Json::array({o.box.x, o.box.y, o.box.width, o.box.height})}});
  }
  d["putative_objects"] = objects;
  d["look_seconds"] = r.look_seconds;
  d["plan"] = plan_json(r.plan);
  if (r.report) {
    d["execution"] = {
        {"frames", r.report->frames},
        {"touched", r.report->touched},
        {"first_touch_frame",
         r.report->first_touch_frame ? core::Json(*r.report->first_touch_frame) : core::Json()},
        {"seconds", r.report->seconds},
        {"episode", r.report->episode_dir.string()}};
    d["ground_truth"] = score_json(r.score);
  }
  core::Json steps = core::Json::array();
  for (const PushStep& s : r.steps) steps.push_back(step_json(s));
  d["pushes"] = steps;
  return r;
}

namespace {

// What marks a directory proprio push wrote: a finished run, or one stopped after its first push.
constexpr std::string_view kPushMarkers[] = {"push.json", "episode/episode.json"};

// The paths the document names inside the staging directory, as they are after the commit.
void unstage_paths(core::Json& j, const std::string& staging, const std::string& final) {
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (s.compare(0, staging.size(), staging) == 0) j = final + s.substr(staging.size());
  } else if (j.is_structured()) {
    for (core::Json& e : j) unstage_paths(e, staging, final);
  }
}

}  // namespace

PushRunResult run_push(const PushOptions& options, const core::Provenance& provenance) {
  options.validate();
  // Written under a hidden name beside --out and swapped in whole at the end (issue 16): an
  // older push's files this one does not write go, and a failed or killed run leaves the old.
  std::optional<core::StagedDirectory> staged;
  PushOptions o = options;
  if (!options.out.empty()) {
    if (fs::exists(options.out) && !options.overwrite) {
      throw Error(options.out.string() + ": already exists (use --overwrite to replace it)");
    }
    staged.emplace(options.out, options.overwrite, kPushMarkers);
    o.out = staged->staging_path();
  }
  o.overwrite = true;  // the directory was checked above
  sim::SimulatedRobot robot(options.table, sim::ObjectCatalogue::load_default());
  if (!o.out.empty()) cv::imwrite((o.out / "before.png").string(), robot.look().image);
  PushRunResult r = push_once(robot, o, provenance);
  if (staged) {
    cv::imwrite((o.out / "after.png").string(), robot.look().image);
    unstage_paths(r.document, o.out.string(), staged->final_path().string());
    r.document["options"]["overwrite"] = options.overwrite;
    if (r.report) r.report->episode_dir = staged->final_path() / r.report->episode_dir.filename();
    for (PushStep& s : r.steps) {
      if (s.report) s.report->episode_dir = staged->final_path() / s.report->episode_dir.filename();
    }
    core::write_json_atomic(o.out / "push.json", r.document);
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

PushEvaluationResult run_push_evaluation(const PushEvaluationOptions& options,
                                         const core::Provenance& provenance) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  PushEvaluationResult r;
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
  core::Json pushes = core::Json::array();
  const sim::ScatterRegion scatter;
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
    sim::SimulatedRobot robot(table, catalogue);
    // The object to push: one of the table's objects (not the clutter, not a distractor).
    std::vector<sim::ObjectTruth> truth = robot.ground_truth();
    std::erase_if(truth,
                  [](const sim::ObjectTruth& o) { return o.role != sim::TableRole::kObject; });
    const sim::ObjectTruth chosen = truth[rng.index(truth.size())];
    // A target min..max_shift away, inside the scatter region.
    Eigen::Vector2d target = chosen.centre.head<2>();
    for (int k = 0; k < 100; ++k) {
      const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
      const double d = rng.uniform(options.min_shift, options.max_shift);
      const Eigen::Vector2d c =
          chosen.centre.head<2>() + d * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (c.x() >= scatter.min.x() && c.x() <= scatter.max.x() && c.y() >= scatter.min.y() &&
          c.y() <= scatter.max.y() && c.norm() >= scatter.base_clearance) {
        target = c;
        break;
      }
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
    core::Json row;
    row["seed"] = seed;
    row["objects"] = table.object_count;
    row["clutter"] = options.clutter;
    row["object"] = chosen.name;
    row["target"] = xy(target);
    row["outcome"] = std::string(core::choice_name(p.outcome, kPushOutcomeNames));
    row["message"] = p.message;
    row["final_distance"] = p.report ? core::Json(p.score.final_distance) : core::Json();
    row["centre_error"] = p.report ? core::Json(p.score.centre_error) : core::Json();
    row["only_intended"] = p.score.only_intended;
    row["touched_other"] = p.score.touched_other;
    row["off_table"] = p.score.off_table;
    row["plan_ms"] = p.plan.seconds * kMs;
    row["pushes"] = p.pushes;
    core::Json steps = core::Json::array();
    for (const PushStep& s : p.steps) {
      steps.push_back(
          {{"true_distance", s.true_distance >= 0 ? core::Json(s.true_distance) : core::Json()},
           {"seen_distance", s.seen_distance >= 0 ? core::Json(s.seen_distance) : core::Json()},
           {"tracked_on_object", s.tracked_on_object},
           {"plan", std::string(core::choice_name(s.plan.outcome, planning::kPlanOutcomeNames))},
           {"executed", s.report.has_value()},
           {"message", s.message}});
    }
    row["steps"] = steps;
    pushes.push_back(row);
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
  core::Json& d = r.document;
  d = core::result_document(kEvaluationFormat, kFormatVersion, provenance);
  d["options"] = core::fields_to_json(options);
  d["planner"] = core::fields_to_json(options.plan);
  d["tables"] = r.tables;
  d["planned"] = r.planned;
  d["not_planned"] = r.not_planned;
  d["not_seen"] = r.not_seen;
  d["refused"] = r.refused;
  d["median_distance"] = r.median_distance >= 0 ? core::Json(r.median_distance) : core::Json();
  d["p90_distance"] = r.p90_distance >= 0 ? core::Json(r.p90_distance) : core::Json();
  d["median_centre_error"] =
      r.median_centre_error >= 0 ? core::Json(r.median_centre_error) : core::Json();
  d["only_intended_rate"] = r.only_intended_rate;
  d["touched_other_rate"] = r.touched_other_rate;
  d["off_table"] = r.off_table;
  d["median_plan_ms"] = r.median_plan_ms;
  d["max_plan_ms"] = r.max_plan_ms;
  d["median_look_ms"] = r.median_look_ms;
  d["median_first_distance"] =
      r.median_first_distance >= 0 ? core::Json(r.median_first_distance) : core::Json();
  d["mean_pushes"] = r.mean_pushes;
  d["tracked_rate"] = r.tracked_rate;
  d["seconds"] = r.seconds;
  d["pushes"] = pushes;
  return r;
}

}  // namespace proprio::loop
