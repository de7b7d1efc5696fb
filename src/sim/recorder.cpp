#include "proprio/sim/recorder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "async_episode_writer.hpp"
#include "backdrop_video.hpp"
#include "camera_shake.hpp"
#include "distractor_mover.hpp"
#include "held_object.hpp"
#include "image_noise.hpp"
#include "lighting_change.hpp"
#include "motion_blur.hpp"
#include "neighbour_nudge.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/random.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "proprio/robot/trajectory.hpp"
#include "proprio/sim/backdrop.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/scene_file.hpp"
#include "proprio/sim/world.hpp"
#include "slider_mover.hpp"
#include "walker_mover.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

namespace {

// The band of table-level points the pusher reaches pointing down (docs/formats/arm-model.md),
// with a margin.
constexpr double kPushStartX = 0.12;
constexpr double kPushEndX = 0.32;
constexpr double kClearance = 0.025;  // least distance, pusher tip to the object's back face, m
// Other objects in the clutter scenario, and sliders in scatter, at the least (thesis 5.1, 6.3.3).
constexpr int kLeastClutter = 6;
constexpr int kLeastSliders = 5;

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

fs::path RecordOptions::default_background_video() { return sim::default_background_video(); }

namespace {
bool is_scenario_file(const std::string& s) { return is_scene_file(s); }

Eigen::Vector3d vec3(const core::Json& j, const std::string& key, const fs::path& file) {
  const auto v = core::json_get<std::vector<double>>(j, key, file);
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw Error::in_file(file, "'" + key + "' must be 3 finite numbers");
  }
  return {v[0], v[1], v[2]};
}

// The default scene with the recording's camera: it looks at the push band from the front and a
// little above, close enough that the object is large in the image.
SceneDescription recording_scene(const RecordOptions& options) {
  SceneDescription scene = default_scene();
  scene.cameras.at(0).width = options.width;
  scene.cameras.at(0).height = options.height;
  scene.cameras.at(0).position = {0.24, -0.62, 0.42};
  scene.cameras.at(0).target = {0.26, 0.04, 0.05};
  return scene;
}

// A scene file: {"objects": [{"type" | shape fields of a catalogue entry, "name", "x", "y",
// "yaw"}], "target": NAME, optional "camera": {"position", "target"}, optional "push":
// {"start", "end"} (metres, robot frame; default: along +x through the target's origin).
ScenarioPlan plan_from_scene(const fs::path& file, const RecordOptions& options,
                             const ObjectCatalogue& catalogue) {
  const core::Json j = read_scene_file(file);
  ScenarioPlan plan;
  plan.scene = recording_scene(options);
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

// Every problem of a scene file names the file (issue 16): also those found by the catalogue
// (an unknown "type") and by the readers of its values.
ScenarioPlan plan_from_file(const fs::path& file, const RecordOptions& options,
                            const ObjectCatalogue& catalogue) {
  try {
    return plan_from_scene(file, options, catalogue);
  } catch (const Error& e) {
    if (std::string_view(e.what()).find(file.string()) != std::string_view::npos) throw;
    throw Error::in_file(file, e.what());
  }
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

RecordSwitches RecordOptions::switches() const {
  RecordSwitches s;
  s.object = is_scenario_file(scenario) ? std::string("(scene file)") : object;
  s.background = moving_background ? "moving" : "static";
  s.distractors = distractor_count();
  s.clutter = clutter;
  if (!scatter_objects.empty()) {
    s.scatter_objects = scatter_objects;
    s.scatter_in_view = scatter_in_view;
  }
  s.push_speed = push_speed;
  s.approach = approach;
  s.width = width;
  s.height = height;
  s.fps = fps;
  s.shadows = shadows;
  s.reflections = reflections;
  s.camera_shake = camera_shake;
  s.lighting_change = lighting_change;
  s.nudge_neighbour = nudge_neighbour;
  s.noise = noise;
  s.motion_blur = motion_blur;
  s.stereo = stereo;
  if (stereo) s.stereo_baseline = stereo_baseline;
  s.depth = depth;
  return s;
}

namespace {

// scatter objects must be catalogue names (plan_walkers takes them as such).
void check_scatter_objects(const RecordOptions& options, const ObjectCatalogue& catalogue) {
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
}

}  // namespace

namespace {

// Clutter: the part of the table where it may stand (m, robot frame), how far it keeps from the
// push corridor's side and from other objects (m), how far from the base axis (m, clear of the
// arm's base), and the draws per object before it is left out.
constexpr double kClutterMinX = 0.08, kClutterMaxX = 0.62;
constexpr double kClutterMinY = -0.30, kClutterMaxY = 0.38;
constexpr double kCorridorMargin = 0.04;
constexpr double kClutterGap = 0.02;
constexpr double kBaseClearance = 0.12;
constexpr int kClutterAttempts = 200;

// A footprint taken on the table: centre (m) and radius (m).
struct Disc {
  Eigen::Vector2d c;
  double r;
};

// Places the target at yaw 0 with its back face the approach ahead of the push's start; returns
// its box centre's x, m.
double place_target(const RecordOptions& options, const ObjectType& target_type,
                    ScenarioPlan& plan) {
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
  return centre_x;
}

// `count` clutter objects of types from `draw_type` at random places, clear of the push corridor
// (beside a target of footprint radius `target_r`, m), of the arm's base and of `taken`; an
// object that finds no room is left out.
void place_clutter(int count, const std::function<std::string()>& draw_type,
                   const ObjectCatalogue& catalogue, double target_r, std::vector<Disc>& taken,
                   core::Rng& rng, ScenarioPlan& plan) {
  for (int i = 0; i < count; ++i) {
    const std::string type = draw_type();
    const ObjectType& t = catalogue.get(type);
    const double r = t.footprint_radius();
    bool placed = false;
    for (int attempt = 0; attempt < kClutterAttempts && !placed; ++attempt) {
      const Eigen::Vector2d p(rng.uniform(kClutterMinX, kClutterMaxX),
                              rng.uniform(kClutterMinY, kClutterMaxY));
      // Keep the push corridor and everything in front of it (toward the camera) free, and
      // stay off the arm's base.
      const double corridor = target_r + r + kCorridorMargin;
      if (p.x() < kPushEndX + target_r + r && p.y() < corridor) continue;
      if (p.norm() < kBaseClearance + r) continue;
      bool overlap = false;
      for (const Disc& d : taken) overlap = overlap || (p - d.c).norm() < d.r + r + kClutterGap;
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
}

}  // namespace

World build_scenario_world(const ScenarioPlan& plan, const ObjectCatalogue& catalogue,
                           const RecordOptions& options) {
  try {
    return World::build(plan.scene, catalogue);
  } catch (const Error& e) {
    if (!is_scenario_file(options.scenario)) throw;
    std::string_view what = e.what();
    constexpr std::string_view kGenerated = "<generated scene>: ";
    if (what.starts_with(kGenerated)) what.remove_prefix(kGenerated.size());
    throw Error::in_file(options.scenario, std::string(what));
  }
}

ScenarioPlan plan_scenario(const RecordOptions& options, const ObjectCatalogue& catalogue) {
  options.validate();
  if (is_scenario_file(options.scenario))
    return plan_from_file(options.scenario, options, catalogue);
  const ObjectType& target_type = catalogue.get(options.object);
  core::Rng rng(options.seed);

  ScenarioPlan plan;
  plan.scene = recording_scene(options);
  // The backdrop just behind the table (the shared layout of sim/backdrop.hpp): the default
  // scene's photograph, or the video (shown from the first frame on).
  set_backdrop(plan.scene, options.moving_background ? Background::kMoving : Background::kPhoto,
               recording_backdrop_layout(), default_background_photo());
  const double centre_x = place_target(options, target_type, plan);
  const Eigen::Vector3d he = target_type.half_extents();
  // push-rotate: the line passes half-way between the centre and the side, so the object turns.
  const double offset = options.scenario == "push-rotate" ? 0.5 * he.y() : 0.0;
  plan.push_start = {kPushStartX, offset, options.pusher_height};
  plan.push_end = {kPushEndX, offset, options.pusher_height};
  if (options.scenario == "hold-3d") plan_hold(options.object, plan);

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
  std::vector<Disc> taken{{Eigen::Vector2d(centre_x, 0.0), target_r}};
  if (options.nudge_neighbour) {
    const PlacedObject o = place_neighbour(draw_type(), catalogue, centre_x, target_r);
    plan.scene.objects.push_back(o);
    plan.neighbour = o.name;
    taken.push_back({o.position, catalogue.get(o.type).footprint_radius()});
  }
  int clutter = options.clutter;
  if (options.scenario == "clutter") clutter = std::max(clutter, kLeastClutter);
  if (options.scenario == "scatter" && !options.scatter_objects.empty()) {
    check_scatter_objects(options, catalogue);
    plan_walkers(options, catalogue, target_r, rng, plan);
    clutter = 0;
  } else if (options.scenario == "scatter") {
    plan_sliders(std::max(clutter, kLeastSliders), draw_type, rng, plan);
    clutter = 0;
  }
  place_clutter(clutter, draw_type, catalogue, target_r, taken, rng, plan);
  if (options.stereo) plan.scene.cameras.at(0).stereo_baseline = options.stereo_baseline;
  for (int i = 0; i < options.distractor_count(); ++i) {
    const PlacedObject o = distractor_start(draw_type(), i);
    plan.scene.objects.push_back(o);
    plan.distractors.push_back(o.name);
  }
  plan.scene.validate();
  return plan;
}

namespace {

// Physics steps before the first frame, for the objects to come to rest on the table (or in the
// grasp).
constexpr int kSettleSteps = 100;
// Depth images hold millimetres (docs/formats/episode.md), the renderer gives metres.
constexpr double kMillimetresPerMetre = 1000.0;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void check_destination(const fs::path& out, const RecordOptions& options) {
  options.validate();
  core::require_output_not_input(out, {options.background_video}, "--out");
  if (fs::exists(out) && !options.overwrite) {
    std::string m = out.string();
    m += ": already exists (use --overwrite to replace it)";
    throw Error(m);
  }
}

// Physics steps per frame; throws Error unless a frame is a whole number of them.
int physics_steps_per_frame(double dt, double fps) {
  const double steps_real = 1.0 / (fps * dt);
  const int steps_per_frame = static_cast<int>(std::lround(steps_real));
  if (steps_per_frame < 1 || std::abs(steps_real - steps_per_frame) > 1e-6) {
    throw Error("fps must divide the physics rate (1 / timestep = " + std::to_string(1.0 / dt) +
                " Hz) into whole steps");
  }
  return steps_per_frame;
}

std::optional<geometry::Camera> right_camera_of(const World& world, bool stereo) {
  if (!stereo) return std::nullopt;
  return world.camera(world.camera_names().at(1));
}

RenderOptions render_options(const RecordOptions& options) {
  RenderOptions ropt;
  ropt.shadows = options.shadows;
  ropt.reflections = options.reflections;
  return ropt;
}

// The arm's push (hold-3d: carry) in joint space, one sample per physics step, from q0.
struct ArmMove {
  robot::JointVector q0;
  double duration = 0.0;  // s
  robot::TrackResult track;
};

ArmMove plan_arm_move(const World& world, const ScenarioPlan& plan, double push_speed) {
  robot::ArmState state(world.arm());
  robot::IkOptions ik;
  const robot::JointVector q_rest = world.arm_joints();
  ArmMove m;
  m.q0 = robot::solve_ik(state, plan.push_start, q_rest, ik).q;
  const robot::BezierTrajectory move =
      plan.held ? carry_move(plan, push_speed)
                : robot::straight_move(plan.push_start, plan.push_end, push_speed);
  robot::TrackOptions track_opt;
  track_opt.rate_hz = 1.0 / world.timestep();
  track_opt.ik = ik;
  m.track = robot::track_trajectory(state, move, m.q0, track_opt);
  m.duration = move.duration();
  return m;
}

// Puts the arm at the start of its move, grasps the target (hold-3d) and lets the objects settle.
// Returns the target's id.
ObjectId set_start(World& world, const ScenarioPlan& plan, const robot::JointVector& q0) {
  world.set_arm_configuration(q0);
  const ObjectId target = world.object(plan.target).id;
  if (plan.held) grasp_target(world, target);
  world.step(kSettleSteps);
  return target;
}

// The frames: still, the arm's move, still, in physics steps, and the frames that cover them.
struct Schedule {
  int steps_per_frame = 1;
  int before_steps = 0;
  int move_steps = 0;
  int total_steps = 0;
  int frame_count = 0;
};

Schedule make_schedule(const RecordOptions& options, double dt, int steps_per_frame,
                       int move_steps) {
  Schedule s;
  s.steps_per_frame = steps_per_frame;
  s.before_steps = static_cast<int>(std::lround(options.still_before / dt));
  s.move_steps = move_steps;
  const int after_steps = static_cast<int>(std::lround(options.still_after / dt));
  s.total_steps = s.before_steps + s.move_steps + after_steps;
  s.frame_count =
      std::min(s.total_steps / steps_per_frame + 1, options.max_frames.value_or(1 << 30));
  return s;
}

// The scenario's scripted motions, played frame by frame.
struct ScriptedMovers {
  ScriptedMovers(const World& world, const ScenarioPlan& plan, std::uint64_t seed)
      : distractors(world, plan.distractors),
        sliders(world, plan.sliders),
        walkers(world, plan, seed) {}

  // Puts the scripted objects where they are at frame `f`, time `t`.
  void move(World& world, int f, double t, double fps) {
    distractors.move(world, t);
    sliders.move(world, t);
    if (f > 0) walkers.advance(1.0 / fps);
    walkers.move(world);
  }

  [[nodiscard]] bool moves(ObjectId id) const {
    const auto in = [id](const std::vector<ObjectId>& ids) {
      return std::find(ids.begin(), ids.end(), id) != ids.end();
    };
    return in(distractors.ids()) || in(sliders.ids()) || in(walkers.ids());
  }

  DistractorMover distractors;
  SliderMover sliders;
  WalkerMover walkers;
};

// The disturbances that are switched on (thesis 5.1). Each draws from a stream of its own, so
// that switching one on leaves the rest alone.
struct Disturbances {
  Disturbances(const World& world, const ScenarioPlan& plan, const RecordOptions& options,
               const Schedule& schedule, double move_duration)
      : noise(options.noise, options.seed), blur(options.motion_blur, schedule.steps_per_frame) {
    if (options.camera_shake) shake.emplace(world, options.seed);
    if (options.lighting_change) lighting.emplace(schedule.total_steps, world.timestep());
    if (!plan.neighbour.empty()) {
      nudge.emplace(world, plan.neighbour, options.still_before, move_duration);
    }
  }

  // The disturbances of the rendered view: they act on mjData's derived camera and light poses,
  // which every step and mj_forward recompute, so they are applied again right before rendering.
  void disturb_view(World& world, double t) {
    if (shake) shake->apply(world);
    if (lighting) lighting->apply(world, t);
  }

  std::optional<CameraShake> shake;
  std::optional<LightingChange> lighting;
  std::optional<NeighbourNudge> nudge;
  ImageNoise noise;
  MotionBlur blur;
};

// One episode's world, arm move, scripted motions and disturbances, set up from the plan; then
// played and rendered frame by frame.
class EpisodeRecording {
 public:
  EpisodeRecording(const RecordOptions& options, const ObjectCatalogue& catalogue)
      : options_(options),
        plan_(plan_scenario(options, catalogue)),
        video_(options.moving_background, options.background_video),
        world_(build_scenario_world(plan_, catalogue, options)),
        steps_per_frame_(physics_steps_per_frame(world_.timestep(), options.fps)),
        renderer_(world_, render_options(options)),
        camera_name_(world_.camera_names().at(0)),
        camera_(world_.camera(camera_name_)),
        right_camera_(right_camera_of(world_, options.stereo)),
        move_(plan_arm_move(world_, plan_, options.push_speed)),
        target_(set_start(world_, plan_, move_.q0)),
        movers_(world_, plan_, options.seed),
        target_start_(world_.object_pose(target_).translation()),
        schedule_(make_schedule(options, world_.timestep(), steps_per_frame_,
                                static_cast<int>(move_.track.joints.size()))),
        disturbances_(world_, plan_, options, schedule_, move_.duration) {}

  [[nodiscard]] episode::EpisodeInfo info(const core::Provenance& run) const;
  [[nodiscard]] std::vector<episode::ObjectInfo> objects() const;
  [[nodiscard]] const geometry::Camera& camera() const { return camera_; }
  [[nodiscard]] const std::optional<geometry::Camera>& right_camera() const {
    return right_camera_;
  }
  [[nodiscard]] int frame_count() const { return schedule_.frame_count; }
  /// Distance the target's origin has moved since the first frame, m.
  [[nodiscard]] double target_moved() const {
    return (world_.object_pose(target_).translation() - target_start_).norm();
  }

  /// Plays and renders every frame into `writer`, then finishes it; timings and the first touch
  /// go to `summary`.
  void record(episode::EpisodeWriter& writer, RecordSummary& summary);

 private:
  bool play_interval(double t);
  cv::Mat render_colour(double t, episode::FrameExtras& extras);
  [[nodiscard]] episode::ArmSample arm_sample(double t, bool touched) const;

  // In the order of set-up (the members are initialised in this order).
  const RecordOptions& options_;
  ScenarioPlan plan_;
  BackdropVideo video_;
  World world_;
  int steps_per_frame_;
  Renderer renderer_;
  std::string camera_name_;
  geometry::Camera camera_;
  std::optional<geometry::Camera> right_camera_;
  ArmMove move_;
  ObjectId target_;
  ScriptedMovers movers_;
  Eigen::Vector3d target_start_;
  Schedule schedule_;
  Disturbances disturbances_;
  int step_index_ = 0;
};

}  // namespace

namespace {

episode::EpisodeInfo EpisodeRecording::info(const core::Provenance& run) const {
  episode::EpisodeInfo info;
  info.fps = options_.fps;
  info.width = options_.width;
  info.height = options_.height;
  info.arm_name = "proprio-sim-arm";
  info.joint_count = robot::kArmJoints;
  info.has_masks = true;
  info.target = target_;
  info.provenance.run = run;
  info.provenance.source = episode::Source::kSimulated;
  info.provenance.scenario = options_.scenario;
  info.provenance.switches = core::fields_to_json(options_.switches());
  info.has_depth = options_.depth;
  info.stereo = options_.stereo;
  return info;
}

// Every object with its role: the scripted movers and the nudged neighbour are distractors.
std::vector<episode::ObjectInfo> EpisodeRecording::objects() const {
  std::vector<episode::ObjectInfo> objects;
  for (const SceneObject& o : world_.objects()) {
    episode::ObjectRole role = episode::ObjectRole::kObject;
    if (o.id == target_) role = episode::ObjectRole::kTarget;
    if (movers_.moves(o.id) || o.name == plan_.neighbour) role = episode::ObjectRole::kDistractor;
    objects.push_back({o.id, o.name, role});
  }
  objects.push_back({kArmId, "arm", episode::ObjectRole::kArm});
  return objects;
}

void EpisodeRecording::record(episode::EpisodeWriter& writer, RecordSummary& summary) {
  std::optional<AsyncEpisodeWriter> async_writer(std::in_place, writer);
  auto clock = Clock::now();
  for (int f = 0; f < schedule_.frame_count; ++f) {
    const double t = f / options_.fps;
    bool touched = f > 0 && play_interval(t);
    movers_.move(world_, f, t, options_.fps);
    // A grasp is a touch: the weld holds the object against the hand.
    if (world_.grasping()) touched = true;
    if (disturbances_.nudge) disturbances_.nudge->apply(world_, t, options_.fps);
    lap(clock, summary.timing.physics);
    if (video_.on()) {
      video_.show_next(world_, renderer_);
      lap(clock, summary.timing.backdrop);
    }
    episode::FrameExtras extras;
    const cv::Mat rgb = render_colour(t, extras);
    lap(clock, summary.timing.render_rgb);
    extras.mask = renderer_.render(world_, camera_name_, kPassMask).mask;
    lap(clock, summary.timing.render_mask);
    if (touched && !summary.first_touch_frame) summary.first_touch_frame = f;
    async_writer->add_frame(rgb, arm_sample(t, touched), std::move(extras));
    clock = Clock::now();
  }
  async_writer->drain();
  summary.timing.write = async_writer->write_seconds();
  summary.timing.write_wait = async_writer->wait_seconds();
  async_writer.reset();
  writer.finish();
  lap(clock, summary.timing.finish);
}

// One frame's interval of physics, ending at `t`: the arm follows its move, a held object turns,
// the motion blur's renders are taken. Returns whether the arm touched the target in any step.
bool EpisodeRecording::play_interval(double t) {
  const double dt = world_.timestep();
  const int steps = schedule_.steps_per_frame;
  bool touched = false;
  for (int s = 0; s < steps; ++s, ++step_index_) {
    const int k = std::clamp(step_index_ - schedule_.before_steps, 0, schedule_.move_steps - 1);
    world_.set_arm_targets(move_.track.joints.q[static_cast<std::size_t>(k)]);
    if (plan_.held) turn_held(world_, t - (steps - s) * dt);
    world_.step();
    touched = touched || world_.arm_touches(target_);
    if (disturbances_.blur.due_after(s)) {
      disturbances_.disturb_view(world_, t);
      disturbances_.blur.add(renderer_.rgb(world_, camera_name_));
    }
  }
  return touched;
}

// The frame's colour image, disturbed, blurred and noisy as the options say; its depth and right
// image go to `extras`.
cv::Mat EpisodeRecording::render_colour(double t, episode::FrameExtras& extras) {
  disturbances_.disturb_view(world_, t);
  const Frame frame =
      renderer_.render(world_, camera_name_, kPassRgb | (options_.depth ? kPassDepth : 0U));
  cv::Mat rgb = frame.rgb;
  disturbances_.blur.finish(rgb);
  if (options_.depth) frame.depth.convertTo(extras.depth, CV_16UC1, kMillimetresPerMetre);
  if (options_.stereo) extras.right_image = renderer_.rgb(world_, world_.camera_names().at(1));
  disturbances_.noise.apply(rgb);
  if (options_.stereo) disturbances_.noise.apply(extras.right_image);
  return rgb;
}

episode::ArmSample EpisodeRecording::arm_sample(double t, bool touched) const {
  episode::ArmSample sample;
  sample.t = t;
  sample.q = world_.arm_joints();
  sample.ee = world_.ee_position();
  sample.ee_image = camera_.project(sample.ee);
  sample.touching = touched;
  return sample;
}

}  // namespace

RecordSummary record_episode(const fs::path& out, const RecordOptions& options,
                             const core::Provenance& run, const ObjectCatalogue& catalogue) {
  const auto wall_start = Clock::now();
  check_destination(out, options);
  EpisodeRecording recording(options, catalogue);
  episode::EpisodeWriterOptions wopt;
  wopt.overwrite = options.overwrite;
  episode::EpisodeWriter writer(out, recording.info(run), recording.camera(), recording.objects(),
                                recording.right_camera(), wopt);
  RecordSummary summary;
  summary.timing.setup = seconds_since(wall_start);
  recording.record(writer, summary);
  summary.frames = recording.frame_count();
  summary.target_moved = recording.target_moved();
  summary.seconds = seconds_since(wall_start);
  summary.fps = summary.frames / summary.seconds;
  summary.message = "recorded " + std::to_string(summary.frames) + " frames of '" +
                    options.scenario + "' with " + options.object;
  return summary;
}

}  // namespace proprio::sim
