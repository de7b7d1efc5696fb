#include "proprio/sim/recorder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "async_episode_writer.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "proprio/robot/trajectory.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/scene_file.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

namespace {

// The band of table-level points the pusher reaches pointing down (docs/formats/arm-model.md),
// with a margin.
constexpr double kPushStartX = 0.12;
constexpr double kPushEndX = 0.32;
constexpr double kClearance = 0.025;  // least distance, pusher tip to the object's back face, m

using Clock = std::chrono::steady_clock;

// Adds the seconds since `t` to `total` and restarts `t`.
void lap(Clock::time_point& t, double& total) {
  const Clock::time_point now = Clock::now();
  total += std::chrono::duration<double>(now - t).count();
  t = now;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) {
    if (!s.empty()) s += ", ";
    s += x;
  }
  return s;
}

}  // namespace

std::vector<std::string> known_scenarios() {
  return {"push", "push-rotate", "clutter", "scatter", "hold-3d"};
}

fs::path RecordOptions::default_background_video() {
  return ObjectCatalogue::default_texture_dir() / "vtest.avi";
}

namespace {
bool is_scenario_file(const std::string& s) { return is_scene_file(s); }

Eigen::Vector3d vec3(const core::Json& j, const std::string& key, const fs::path& file) {
  const auto v = core::json_get<std::vector<double>>(j, key, file);
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw Error::in_file(file, "'" + key + "' must be 3 finite numbers");
  }
  return {v[0], v[1], v[2]};
}

// A scene file: {"objects": [{"type" | shape fields of a catalogue entry, "name", "x", "y",
// "yaw"}], "target": NAME, optional "camera": {"position", "target"}, optional "push":
// {"start", "end"} (metres, robot frame; default: along +x through the target's origin).
ScenarioPlan plan_from_file(const fs::path& file, const RecordOptions& options,
                            const ObjectCatalogue& catalogue) {
  const core::Json j = read_scene_file(file);
  ScenarioPlan plan;
  plan.scene = default_scene();
  plan.scene.cameras.at(0).width = options.width;
  plan.scene.cameras.at(0).height = options.height;
  plan.scene.cameras.at(0).position = {0.24, -0.62, 0.42};
  plan.scene.cameras.at(0).target = {0.26, 0.04, 0.05};
  if (!j.contains("objects") || !j["objects"].is_array() || j["objects"].empty()) {
    throw Error::in_file(file, "'objects' must be a non-empty array");
  }
  for (const core::Json& o : j["objects"]) {
    PlacedObject p;
    if (o.contains("type")) {
      p.type = core::json_get<std::string>(o, "type", file);
      (void)catalogue.get(p.type);
    } else {
      p.custom =
          parse_object_type(o, file, {file.parent_path(), ObjectCatalogue::default_texture_dir()});
      p.type = p.custom->name;
    }
    p.name = o.contains("name") ? core::json_get<std::string>(o, "name", file) : p.type;
    p.position = {core::json_get<double>(o, "x", file), core::json_get<double>(o, "y", file)};
    p.yaw = o.contains("yaw") ? core::json_get<double>(o, "yaw", file) : 0.0;
    plan.scene.objects.push_back(p);
  }
  plan.target = core::json_get<std::string>(j, "target", file);
  const auto it = std::find_if(plan.scene.objects.begin(), plan.scene.objects.end(),
                               [&](const PlacedObject& p) { return p.name == plan.target; });
  if (it == plan.scene.objects.end()) {
    throw Error::in_file(file, "target '" + plan.target + "' is not one of the objects");
  }
  if (j.contains("camera")) {
    plan.scene.cameras.at(0).position = vec3(j["camera"], "position", file);
    plan.scene.cameras.at(0).target = vec3(j["camera"], "target", file);
  }
  if (j.contains("push")) {
    plan.push_start = vec3(j["push"], "start", file);
    plan.push_end = vec3(j["push"], "end", file);
  } else {
    plan.push_start = {kPushStartX, it->position.y(), options.pusher_height};
    plan.push_end = {kPushEndX, it->position.y(), options.pusher_height};
  }
  if (options.stereo) plan.scene.cameras.at(0).stereo_baseline = options.stereo_baseline;
  try {
    plan.scene.validate();
  } catch (const Error& e) {
    throw Error::in_file(file, e.what());
  }
  return plan;
}
}  // namespace

void RecordOptions::validate() const {
  const auto names = known_scenarios();
  if (!is_scenario_file(scenario) &&
      std::find(names.begin(), names.end(), scenario) == names.end()) {
    std::string m = "unknown scenario '";
    m += scenario;
    m += "' (known: ";
    m += join(names);
    m += ", or a scene FILE.json / FILE.yaml)";
    throw Error(m);
  }
  require(width >= 16 && height >= 16 && width <= 4096 && height <= 4096,
          "image size must be 16..4096 pixels per side");
  require(std::isfinite(fps) && fps > 0 && fps <= 1000, "fps must be in (0, 1000]");
  require(std::isfinite(push_speed) && push_speed > 0 && push_speed <= 1.0,
          "push speed must be in (0, 1] m/s");
  require(std::isfinite(still_before) && still_before >= 0 && std::isfinite(still_after) &&
              still_after >= 0,
          "still times must be >= 0 s");
  require(std::isfinite(pusher_height) && pusher_height > 0 && pusher_height < 0.2,
          "pusher height must be in (0, 0.2) m");
  require(std::isfinite(approach) && approach >= kClearance && approach <= 0.15,
          "approach must be in [0.025, 0.15] m");
  require(!max_frames || *max_frames >= 1, "max frames must be >= 1");
  require(clutter >= 0 && clutter <= 8, "clutter must be 0..8 objects");
  if (!scatter_objects.empty()) {
    require(scenario == "scatter", "scatter objects are for the scatter scenario only");
    require(scatter_objects.size() <= 8, "scatter objects: at most 8");
  } else {
    require(!scatter_in_view, "scatter in view needs scatter objects");
  }
  if (!scatter_objects.empty()) {
    for (std::size_t i = 0; i < scatter_objects.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        if (scatter_objects[i] == scatter_objects[j]) {
          std::string m = "scatter object '";
          m += scatter_objects[i];
          m += "' is given twice";
          throw Error(m);
        }
      }
    }
    if (std::find(scatter_objects.begin(), scatter_objects.end(), object) ==
        scatter_objects.end()) {
      std::string m = "the target '";
      m += object;
      m += "' is not one of the scatter objects (";
      m += join(scatter_objects);
      m += "): choose it with --object";
      throw Error(m);
    }
  }
  require(distractor_count() >= 0 && distractor_count() <= 4, "distractors must be 0..4 objects");
  require(std::isfinite(noise) && noise >= 0 && noise <= 100, "noise must be 0..100 grey levels");
  require(std::isfinite(stereo_baseline) && stereo_baseline > 0 && stereo_baseline <= 1.0,
          "stereo baseline must be in (0, 1] m");
}

int RecordOptions::distractor_count() const {
  return distractors.value_or(moving_background ? 2 : 0);
}

core::Json RecordOptions::switches() const {
  core::Json j = core::Json::object();
  j["object"] = is_scenario_file(scenario) ? std::string("(scene file)") : object;
  j["background"] = moving_background ? "moving" : "static";
  j["distractors"] = distractor_count();
  j["clutter"] = clutter;
  if (!scatter_objects.empty()) {
    j["scatter_objects"] = scatter_objects;
    j["scatter_in_view"] = scatter_in_view;
  }
  j["push_speed"] = push_speed;
  j["approach"] = approach;
  j["width"] = width;
  j["height"] = height;
  j["fps"] = fps;
  j["shadows"] = shadows;
  j["reflections"] = reflections;
  j["camera_shake"] = camera_shake;
  j["lighting_change"] = lighting_change;
  j["nudge_neighbour"] = nudge_neighbour;
  j["noise"] = noise;
  j["motion_blur"] = motion_blur;
  j["stereo"] = stereo;
  j["stereo_baseline"] = stereo ? core::Json(stereo_baseline) : core::Json();
  j["depth"] = depth;
  return j;
}

namespace {

// The walkers' box: x well beyond the camera's view of the table (about -0.3..0.85 m at
// y = 0.3, computed from the camera below), so that they leave it and come back; y from behind
// the push corridor to the backdrop (y = 0.56).
constexpr double kWalkMinX = -0.55, kWalkMaxX = 1.05, kWalkMaxY = 0.54;
// The part of that box that the camera sees whole at every y (about -0.2..0.74 m at y = 0.15).
constexpr double kViewMinX = -0.1, kViewMaxX = 0.62;
constexpr double kWalkGap = 0.01;  // least distance between two walkers' footprints, m

// scatter with chosen objects: the objects other than the target become walkers, started at
// random non-overlapping places in view, heading anywhere, 0.06-0.16 m/s.
void plan_walkers(const RecordOptions& options, const ObjectCatalogue& catalogue, double target_r,
                  core::Rng& rng, ScenarioPlan& plan) {
  for (const std::string& name : options.scatter_objects) {
    const auto known = catalogue.names();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string m = "unknown scatter object '";
      m += name;
      m += "' (known: ";
      m += join(known);
      m += ")";
      throw Error(m);
    }
  }
  plan.walk_min = {options.scatter_in_view ? kViewMinX : kWalkMinX, 0.0};
  plan.walk_max = {options.scatter_in_view ? kViewMaxX : kWalkMaxX, kWalkMaxY};
  std::vector<ScenarioPlan::Walker> walkers;
  for (const std::string& name : options.scatter_objects) {
    if (name == options.object) continue;
    ScenarioPlan::Walker w;
    w.name = "scatter-" + name;
    w.radius = catalogue.get(name).footprint_radius();
    w.y_min = target_r + w.radius + 0.03;
    if (w.y_min > kWalkMaxY - w.radius) {
      std::string m = "scatter object '";
      m += name;
      m += "' is too large to wander behind the target";
      throw Error(m);
    }
    walkers.push_back(w);
  }
  // Start places in view, drawn one after the other; where the last ones find no room the
  // whole draw starts again.
  bool placed_all = false;
  for (int round = 0; round < 50 && !placed_all; ++round) {
    placed_all = true;
    for (std::size_t i = 0; i < walkers.size() && placed_all; ++i) {
      ScenarioPlan::Walker& w = walkers[i];
      bool placed = false;
      for (int attempt = 0; attempt < 200 && !placed; ++attempt) {
        const Eigen::Vector2d p(rng.uniform(kViewMinX, kViewMaxX),
                                rng.uniform(w.y_min, kWalkMaxY - w.radius));
        bool overlap = false;
        for (std::size_t j = 0; j < i; ++j)
          overlap =
              overlap || (p - walkers[j].position).norm() < walkers[j].radius + w.radius + kWalkGap;
        if (overlap) continue;
        w.position = p;
        placed = true;
      }
      placed_all = placed;
    }
  }
  if (!placed_all) throw Error("scatter objects: no room for them all on the table");
  for (ScenarioPlan::Walker& w : walkers) {
    w.heading = rng.uniform(-std::numbers::pi, std::numbers::pi);
    w.speed = rng.uniform(0.06, 0.16);
    w.yaw = rng.uniform(-std::numbers::pi, std::numbers::pi);
    PlacedObject o;
    o.type = w.name.substr(std::string("scatter-").size());
    o.name = w.name;
    o.position = w.position;
    o.yaw = w.yaw;
    plan.scene.objects.push_back(o);
    plan.walkers.push_back(w);
  }
}

// One frame (dt seconds) of the walkers' random walk: heading and speed drift, the walkers bounce
// off the box's walls and turn back from each other.
void advance_walkers(std::vector<ScenarioPlan::Walker>& walkers, const Eigen::Vector2d& lo,
                     const Eigen::Vector2d& hi, double dt, core::Rng& rng) {
  for (std::size_t i = 0; i < walkers.size(); ++i) {
    ScenarioPlan::Walker& w = walkers[i];
    w.heading += rng.normal() * 1.5 * std::sqrt(dt);
    w.speed = std::clamp(w.speed + rng.normal() * 0.05 * std::sqrt(dt), 0.06, 0.2);
    w.yaw += rng.normal() * 1.0 * std::sqrt(dt) + 0.5 * dt;
    Eigen::Vector2d p =
        w.position + w.speed * dt * Eigen::Vector2d(std::cos(w.heading), std::sin(w.heading));
    if (p.x() < lo.x() || p.x() > hi.x()) w.heading = std::numbers::pi - w.heading;
    if (p.y() < std::max(lo.y(), w.y_min) || p.y() > hi.y() - w.radius) w.heading = -w.heading;
    p = w.position + w.speed * dt * Eigen::Vector2d(std::cos(w.heading), std::sin(w.heading));
    bool blocked = p.x() < lo.x() || p.x() > hi.x() || p.y() < std::max(lo.y(), w.y_min) ||
                   p.y() > hi.y() - w.radius;
    for (std::size_t j = 0; j < walkers.size() && !blocked; ++j) {
      if (j == i) continue;
      const double d = (p - walkers[j].position).norm();
      // Only moves that bring two walkers closer are refused, so that two that touch part.
      blocked = d < w.radius + walkers[j].radius + kWalkGap &&
                d < (w.position - walkers[j].position).norm();
    }
    if (blocked) {
      w.heading += std::numbers::pi;
    } else {
      w.position = p;
    }
  }
}

}  // namespace

ScenarioPlan plan_scenario(const RecordOptions& options, const ObjectCatalogue& catalogue) {
  options.validate();
  if (is_scenario_file(options.scenario))
    return plan_from_file(options.scenario, options, catalogue);
  const ObjectType& target_type = catalogue.get(options.object);
  core::Rng rng(options.seed);

  ScenarioPlan plan;
  plan.scene = default_scene();
  plan.scene.cameras.at(0).width = options.width;
  plan.scene.cameras.at(0).height = options.height;
  // Look at the push band from the front and a little above, close enough that the object is
  // large in the image.
  plan.scene.cameras.at(0).position = {0.24, -0.62, 0.42};
  plan.scene.cameras.at(0).target = {0.26, 0.04, 0.05};
  // A backdrop just behind the table, low enough that the camera sees the middle of its picture
  // (where vtest.avi's people walk), with the video's 4:3 aspect.
  plan.scene.backdrop.center = {0.30, 0.56, 0.30};
  plan.scene.backdrop.size = {1.8, 0.9};
  plan.scene.backdrop.texture_width = 384;
  plan.scene.backdrop.texture_height = 288;

  // Target at yaw 0: its box spans [cx - hx, cx + hx] along x about its origin.
  const Eigen::Vector3d he = target_type.half_extents();
  const Eigen::Vector3d ce = target_type.center();
  // The approach is shortened for long objects, so that the push stays within reach.
  const double room = kPushEndX - 0.021 - kPushStartX - he.x();
  const double back = kPushStartX + std::max(kClearance, std::min(options.approach, room));
  const double centre_x = back + he.x();
  if (centre_x >= kPushEndX - 0.02) {
    std::string m = "object '";
    m += options.object;
    m += "' is too long to be pushed within the arm's reach";
    throw Error(m);
  }
  PlacedObject target;
  target.type = options.object;
  target.name = options.object;
  target.position = {centre_x - ce.x(), -ce.y()};
  plan.scene.objects.push_back(target);
  plan.target = options.object;

  // push-rotate: the line passes half-way between the centre and the side, so the object turns.
  const double offset = options.scenario == "push-rotate" ? 0.5 * he.y() : 0.0;
  plan.push_start = {kPushStartX, offset, options.pusher_height};
  plan.push_end = {kPushEndX, offset, options.pusher_height};
  if (options.scenario == "hold-3d") {
    plan.held = true;
    plan.push_start = {0.18, -0.08, 0.13};
    plan.via = {0.24, 0.06, 0.21};
    plan.push_end = {0.27, -0.04, 0.15};
    plan.scene.grasp_object = options.object;
  }

  // Clutter and distractors: other catalogue objects, drawn without repetition.
  std::vector<std::string> pool;
  for (const auto& n : catalogue.names())
    if (n != options.object) pool.push_back(n);
  auto draw_type = [&]() -> std::string {
    if (pool.empty()) throw Error("not enough catalogue objects for the clutter and distractors");
    const auto k = static_cast<std::ptrdiff_t>(rng.index(pool.size()));
    std::string n = pool[static_cast<std::size_t>(k)];
    pool.erase(pool.begin() + k);
    return n;
  };
  const double target_r = std::hypot(he.x(), he.y());
  struct Disc {
    Eigen::Vector2d c;
    double r;
  };
  std::vector<Disc> taken{{Eigen::Vector2d(centre_x, 0.0), target_r}};
  if (options.nudge_neighbour) {
    // Beside the push path, toward the back, clear of the pusher.
    PlacedObject o;
    o.type = draw_type();
    o.name = "neighbour-" + o.type;
    const double r = catalogue.get(o.type).footprint_radius();
    o.position = {centre_x, target_r + r + 0.03};
    plan.scene.objects.push_back(o);
    plan.neighbour = o.name;
    taken.push_back({o.position, r});
  }
  int clutter = options.clutter;
  if (options.scenario == "clutter") clutter = std::max(clutter, 6);
  if (options.scenario == "scatter" && !options.scatter_objects.empty()) {
    plan_walkers(options, catalogue, target_r, rng, plan);
    clutter = 0;
  } else if (options.scenario == "scatter") {
    for (int i = 0; i < std::max(clutter, 5); ++i) {
      PlacedObject o;
      o.type = draw_type();
      o.name = "scatter-" + o.type;
      const double y = 0.2 + 0.06 * i;
      const double x0 = rng.uniform(-0.5, 1.0);
      const double speed = rng.uniform(0.08, 0.2) * (rng.uniform() < 0.5 ? -1.0 : 1.0);
      o.position = {x0, y};
      plan.scene.objects.push_back(o);
      plan.sliders.push_back({o.name, x0, y, speed});
    }
    clutter = 0;
  }
  for (int i = 0; i < clutter; ++i) {
    const std::string type = draw_type();
    const ObjectType& t = catalogue.get(type);
    const double r = t.footprint_radius();
    bool placed = false;
    for (int attempt = 0; attempt < 200 && !placed; ++attempt) {
      const Eigen::Vector2d p(rng.uniform(0.08, 0.62), rng.uniform(-0.30, 0.38));
      // Keep the push corridor and everything in front of it (toward the camera) free, and
      // stay off the arm's base.
      const double corridor = target_r + r + 0.04;
      if (p.x() < kPushEndX + target_r + r && p.y() < corridor) continue;
      if (p.norm() < 0.12 + r) continue;
      bool overlap = false;
      for (const Disc& d : taken) overlap = overlap || (p - d.c).norm() < d.r + r + 0.02;
      if (overlap) continue;
      PlacedObject o;
      o.type = type;
      o.name = type;
      o.position = p;
      o.yaw = rng.uniform(-std::numbers::pi, std::numbers::pi);
      plan.scene.objects.push_back(o);
      taken.push_back({p, r});
      placed = true;
    }
  }
  if (options.stereo) plan.scene.cameras.at(0).stereo_baseline = options.stereo_baseline;
  {
    for (int i = 0; i < options.distractor_count(); ++i) {
      PlacedObject o;
      o.type = draw_type();
      o.name = "distractor-" + o.type;
      // Start positions; record_episode moves them along y = 0.46 (behind everything).
      o.position = {0.15 + 0.3 * i, 0.46};
      plan.scene.objects.push_back(o);
      plan.distractors.push_back(o.name);
    }
  }
  plan.scene.validate();
  return plan;
}

RecordSummary record_episode(const fs::path& out, const RecordOptions& options,
                             const core::Provenance& run, const ObjectCatalogue& catalogue) {
  const auto wall_start = std::chrono::steady_clock::now();
  options.validate();
  if (fs::exists(out) && !options.overwrite) {
    std::string m = out.string();
    m += ": already exists (use --overwrite to replace it)";
    throw Error(m);
  }
  const ScenarioPlan plan = plan_scenario(options, catalogue);

  cv::VideoCapture video;
  if (options.moving_background) {
    if (!fs::is_regular_file(options.background_video)) {
      throw Error::in_file(options.background_video, "no such background video");
    }
    video.open(options.background_video.string());
    if (!video.isOpened()) {
      throw Error::in_file(options.background_video, "cannot open the background video");
    }
  }

  World world = World::build(plan.scene, catalogue);
  const double dt = world.timestep();
  const double steps_real = 1.0 / (options.fps * dt);
  const int steps_per_frame = static_cast<int>(std::lround(steps_real));
  if (steps_per_frame < 1 || std::abs(steps_real - steps_per_frame) > 1e-6) {
    throw Error("fps must divide the physics rate (1 / timestep = " + std::to_string(1.0 / dt) +
                " Hz) into whole steps");
  }
  RenderOptions ropt;
  ropt.shadows = options.shadows;
  ropt.reflections = options.reflections;
  Renderer renderer(world, ropt);
  const std::string camera_name = world.camera_names().at(0);
  const geometry::Camera camera = world.camera(camera_name);
  std::optional<geometry::Camera> right_camera;
  if (options.stereo) right_camera = world.camera(world.camera_names().at(1));

  // The push, in joint space, one sample per physics step.
  robot::ArmState state(world.arm());
  robot::IkOptions ik;
  const robot::JointVector q_rest = world.arm_joints();
  const robot::JointVector q0 = robot::solve_ik(state, plan.push_start, q_rest, ik).q;
  const robot::BezierTrajectory move =
      plan.held ? robot::BezierTrajectory(
                      plan.push_start, plan.via, plan.push_end,
                      ((plan.via - plan.push_start).norm() + (plan.push_end - plan.via).norm()) /
                          std::min(options.push_speed, 0.06))
                : robot::straight_move(plan.push_start, plan.push_end, options.push_speed);
  robot::TrackOptions track_opt;
  track_opt.rate_hz = 1.0 / dt;
  track_opt.ik = ik;
  const robot::TrackResult track = robot::track_trajectory(state, move, q0, track_opt);
  world.set_arm_configuration(q0);
  const ObjectId target_id = world.object(plan.target).id;
  // hold-3d: the target is grasped at the start, its top face 1 cm under the pusher tip and
  // turned with the arm, by the weld constraint of the scene (World::set_grasp): from then on
  // the physics carries it. The fingers do not close on it: the arm's jaws span the pusher, not
  // an object below it, so the weld stands in for the grip.
  const ObjectType& target_type = world.object(target_id).type;
  if (plan.held) {
    const Eigen::Vector3d ee = world.ee_position();
    const Eigen::Vector3d he = target_type.half_extents();
    const Eigen::Vector3d ce = target_type.center();
    Pose p = Pose::Identity();
    p.linear() =
        Eigen::AngleAxisd(std::atan2(ee.y(), ee.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.translation() = ee - Eigen::Vector3d(0, 0, 0.01 + he.z()) - p.linear() * ce;
    world.set_object_pose(target_id, p);
    world.set_grasp(true, ce);
  }
  // Let the objects settle on the table (or in the grasp) before the first frame.
  world.step(100);

  std::vector<ObjectId> distractor_ids;
  for (const auto& n : plan.distractors) distractor_ids.push_back(world.object(n).id);
  std::vector<ObjectId> slider_ids;
  for (const auto& sl : plan.sliders) slider_ids.push_back(world.object(sl.name).id);
  std::vector<ObjectId> walker_ids;
  for (const auto& w : plan.walkers) walker_ids.push_back(world.object(w.name).id);
  std::vector<ScenarioPlan::Walker> walkers = plan.walkers;
  core::Rng walk_rng(options.seed ^ 0x57414c4bULL);
  const Eigen::Vector3d target_start = world.object_pose(target_id).translation();

  episode::EpisodeInfo info;
  info.fps = options.fps;
  info.width = options.width;
  info.height = options.height;
  info.arm_name = "proprio-sim-arm";
  info.joint_count = robot::kArmJoints;
  info.has_masks = true;
  info.target = target_id;
  info.provenance.run = run;
  info.provenance.source = episode::Source::kSimulated;
  info.provenance.scenario = options.scenario;
  info.provenance.switches = options.switches();
  std::vector<episode::ObjectInfo> objects;
  for (const SceneObject& o : world.objects()) {
    episode::ObjectRole role = episode::ObjectRole::kObject;
    if (o.id == target_id) role = episode::ObjectRole::kTarget;
    if (std::find(distractor_ids.begin(), distractor_ids.end(), o.id) != distractor_ids.end() ||
        std::find(slider_ids.begin(), slider_ids.end(), o.id) != slider_ids.end() ||
        std::find(walker_ids.begin(), walker_ids.end(), o.id) != walker_ids.end() ||
        o.name == plan.neighbour)
      role = episode::ObjectRole::kDistractor;
    objects.push_back({o.id, o.name, role});
  }
  objects.push_back({kArmId, "arm", episode::ObjectRole::kArm});
  episode::EpisodeWriterOptions wopt;
  wopt.overwrite = options.overwrite;
  info.has_depth = options.depth;
  info.stereo = options.stereo;
  episode::EpisodeWriter writer(out, info, camera, objects, right_camera, wopt);
  RecordSummary summary;
  summary.timing.setup = std::chrono::duration<double>(Clock::now() - wall_start).count();

  const int before_steps = static_cast<int>(std::lround(options.still_before / dt));
  const int move_steps = static_cast<int>(track.joints.size());
  const int after_steps = static_cast<int>(std::lround(options.still_after / dt));
  const int total_steps = before_steps + move_steps + after_steps;
  const int frame_count =
      std::min(total_steps / steps_per_frame + 1, options.max_frames.value_or(1 << 30));

  // Disturbances draw from their own streams so that switching one on leaves the rest alone.
  core::Rng shake_rng(options.seed ^ 0x5348414b45ULL);
  cv::RNG noise_rng(options.seed ^ 0x4e4f495345ULL);
  const int blur_renders = options.motion_blur ? 4 : 1;
  const int blur_every = std::max(1, steps_per_frame / blur_renders);
  std::vector<int> camera_ids;
  for (const auto& n : world.camera_names()) camera_ids.push_back(world.camera_id(n));
  const ObjectId neighbour_id = plan.neighbour.empty() ? 0 : world.object(plan.neighbour).id;
  const Pose neighbour_start = neighbour_id ? world.object_pose(neighbour_id) : Pose::Identity();
  const double nudge_t0 = options.still_before + 0.3 * move.duration();
  const double lighting_t = 0.5 * total_steps * dt;

  // The disturbances of the rendered view: they act on mjData's derived camera and light poses,
  // which every step and mj_forward recompute, so they are applied again right before rendering.
  auto disturb_view = [&](double t) {
    mjData& d = world.data();
    if (options.camera_shake) {
      const Eigen::Vector3d dp(shake_rng.uniform(-0.004, 0.004), shake_rng.uniform(-0.004, 0.004),
                               shake_rng.uniform(-0.004, 0.004));
      const Eigen::Vector3d axis(shake_rng.normal(), shake_rng.normal(), shake_rng.normal());
      const double angle = shake_rng.uniform(-0.007, 0.007);
      const Eigen::Matrix3d dr = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
      for (int id : camera_ids) {
        Eigen::Map<Eigen::Vector3d> pos(d.cam_xpos + 3 * id);
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(d.cam_xmat + 9 * id);
        pos += dp;
        rot = (dr * rot).eval();
      }
    }
    if (options.lighting_change && t >= lighting_t && world.model().nlight > 0) {
      Eigen::Map<Eigen::Vector3d> pos(d.light_xpos);
      Eigen::Map<Eigen::Vector3d> dir(d.light_xdir);
      pos = Eigen::Vector3d(0.9, -0.6, 1.0);
      dir = (Eigen::Vector3d(0.3, 0.05, 0.0) - pos).normalized();
    }
  };
  auto render_rgb = [&](double t) {
    disturb_view(t);
    return renderer.rgb(world, camera_name);
  };

  // hold-3d: the hand turns the object in its grip a little so that the views change in 3D.
  auto turn_held = [&](double t) {
    world.set_grasp_rotation((Eigen::AngleAxisd(0.6 * std::sin(0.9 * t), Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(0.15 * std::sin(1.3 * t), Eigen::Vector3d::UnitX()))
                                 .toRotationMatrix());
  };
  int step_index = 0;
  std::optional<AsyncEpisodeWriter> async_writer(std::in_place, writer);
  auto clock = Clock::now();
  for (int f = 0; f < frame_count; ++f) {
    bool touched = false;
    const double t = f / options.fps;
    cv::Mat blur_sum;
    if (f > 0) {
      for (int s = 0; s < steps_per_frame; ++s, ++step_index) {
        const int k = std::clamp(step_index - before_steps, 0, move_steps - 1);
        world.set_arm_targets(track.joints.q[static_cast<std::size_t>(k)]);
        if (plan.held) turn_held(t - (steps_per_frame - s) * dt);
        world.step();
        touched = touched || world.arm_touches(target_id);
        if (options.motion_blur && (s + 1) % blur_every == 0 && s + 1 < steps_per_frame) {
          cv::Mat sub;
          render_rgb(t).convertTo(sub, CV_32FC3);
          if (blur_sum.empty()) {
            blur_sum = sub;
          } else {
            blur_sum += sub;
          }
        }
      }
    }
    for (std::size_t i = 0; i < distractor_ids.size(); ++i) {
      const SceneObject& o = world.object(distractor_ids[i]);
      Pose p = Pose::Identity();
      const double phase = 2.0 * std::numbers::pi * (0.15 * t + 0.5 * static_cast<double>(i));
      p.translation() =
          Eigen::Vector3d(0.35 + 0.30 * std::sin(phase), 0.46, o.type.bottom() + 0.001);
      p.linear() = Eigen::AngleAxisd(0.8 * t + static_cast<double>(i), Eigen::Vector3d::UnitZ())
                       .toRotationMatrix();
      world.set_object_pose(distractor_ids[i], p);
    }
    for (std::size_t i = 0; i < slider_ids.size(); ++i) {
      const ScenarioPlan::Slider& sl = plan.sliders[i];
      const double x = std::fmod(sl.x0 + sl.speed * t + 0.5 + 15.0, 1.5) - 0.5;
      Pose p = Pose::Identity();
      p.translation() = Eigen::Vector3d(x, sl.y, world.object(slider_ids[i]).type.bottom() + 0.001);
      p.linear() = Eigen::AngleAxisd(3.0 * x, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      world.set_object_pose(slider_ids[i], p);
    }
    if (f > 0) advance_walkers(walkers, plan.walk_min, plan.walk_max, 1.0 / options.fps, walk_rng);
    for (std::size_t i = 0; i < walker_ids.size(); ++i) {
      const ScenarioPlan::Walker& w = walkers[i];
      Pose p = Pose::Identity();
      p.translation() = Eigen::Vector3d(w.position.x(), w.position.y(),
                                        world.object(walker_ids[i]).type.bottom() + 0.001);
      p.linear() = Eigen::AngleAxisd(w.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      world.set_object_pose(walker_ids[i], p);
    }
    // A grasp is a touch: the weld holds the object against the hand.
    if (world.grasping()) touched = true;
    if (neighbour_id && t >= nudge_t0 && t - nudge_t0 <= 0.5 + 0.5 / options.fps) {
      // Shoved 5 cm away from the push path over half a second.
      const double u = std::min(1.0, (t - nudge_t0) / 0.5);
      Pose p = neighbour_start;
      p.translation().y() += 0.05 * u;
      p.translation().z() += 0.001;
      world.set_object_pose(neighbour_id, p);
    }
    lap(clock, summary.timing.physics);
    if (video.isOpened()) {
      cv::Mat vf;
      if (!video.read(vf) || vf.empty()) {
        video.set(cv::CAP_PROP_POS_FRAMES, 0);
        video.read(vf);
      }
      if (vf.empty()) throw Error::in_file(options.background_video, "cannot read a frame");
      world.set_texture_image(kBackdropTexture, vf);
      renderer.upload_texture(world, kBackdropTexture);
      lap(clock, summary.timing.backdrop);
    }
    disturb_view(t);
    const Frame frame =
        renderer.render(world, camera_name, kPassRgb | (options.depth ? kPassDepth : 0U));
    cv::Mat rgb = frame.rgb;
    if (!blur_sum.empty()) {
      cv::Mat last;
      rgb.convertTo(last, CV_32FC3);
      blur_sum += last;
      blur_sum.convertTo(rgb, CV_8UC3, 1.0 / blur_renders);
    }
    episode::FrameExtras extras;
    if (options.depth) frame.depth.convertTo(extras.depth, CV_16UC1, 1000.0);
    if (options.stereo) extras.right_image = renderer.rgb(world, world.camera_names().at(1));
    auto add_noise = [&](cv::Mat& img) {
      if (options.noise <= 0) return;
      cv::Mat n(img.size(), CV_16SC3);
      noise_rng.fill(n, cv::RNG::NORMAL, 0.0, options.noise);
      cv::Mat noisy;
      cv::add(img, n, noisy, cv::noArray(), CV_8UC3);
      img = noisy;
    };
    add_noise(rgb);
    if (options.stereo) add_noise(extras.right_image);
    lap(clock, summary.timing.render_rgb);
    extras.mask = renderer.render(world, camera_name, kPassMask).mask;
    lap(clock, summary.timing.render_mask);

    episode::ArmSample sample;
    sample.t = t;
    sample.q = world.arm_joints();
    sample.ee = world.ee_position();
    sample.ee_image = camera.project(sample.ee);
    sample.touching = touched;
    if (touched && !summary.first_touch_frame) summary.first_touch_frame = f;
    async_writer->add_frame(rgb, sample, std::move(extras));
    clock = Clock::now();
  }
  async_writer->drain();
  summary.timing.write = async_writer->write_seconds();
  summary.timing.write_wait = async_writer->wait_seconds();
  async_writer.reset();
  writer.finish();
  lap(clock, summary.timing.finish);

  summary.frames = frame_count;
  summary.target_moved = (world.object_pose(target_id).translation() - target_start).norm();
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  summary.fps = summary.frames / summary.seconds;
  summary.message = "recorded " + std::to_string(frame_count) + " frames of '" + options.scenario +
                    "' with " + options.object;
  return summary;
}

}  // namespace proprio::sim
