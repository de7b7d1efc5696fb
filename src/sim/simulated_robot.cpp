#include "proprio/sim/simulated_robot.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxTableObjects = 8;
constexpr int kScatterAttempts = 400;
constexpr int kSettleSteps = 150;       // physics steps for objects to come to rest (0.3 s)
constexpr double kFallenBelow = -0.01;  // m: an object's origin below the table top is off
// Where the arm waits between pushes, j1..j5 (rad): turned toward -x, upper arm raised, forearm
// and hand folded up.
constexpr std::array<double, robot::kArmJoints> kParkJoints{2.9, 0.3, 1.2, 1.0, 0.0};

}  // namespace

void TableOptions::validate() const {
  core::check_field_bounds(*this, "table");
  require(objects.size() <= static_cast<std::size_t>(kMaxTableObjects), "table: at most 8 objects");
}

namespace {

// An object's footprint on the table: its bounding box turned by its yaw (m).
struct Footprint {
  Eigen::Vector2d c;    // box centre
  Eigen::Vector2d h;    // half extents
  Eigen::Matrix2d rot;  // columns: the box's axes
};

Footprint footprint(const ObjectType& t, const Eigen::Vector2d& position, double yaw) {
  Footprint f;
  f.rot = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  f.c = position + f.rot * t.center().head<2>();
  f.h = t.half_extents().head<2>();
  return f;
}

// Overlap of two footprints grown by `gap` / 2 each: the least penetration over the separating
// axes of both boxes (0 when they are apart).
double overlap(const Footprint& a, const Footprint& b, double gap) {
  double least = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d d = b.c - a.c;
  for (const Footprint* f : {&a, &b}) {
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector2d axis = f->rot.col(k);
      const double ra =
          a.h.x() * std::abs(axis.dot(a.rot.col(0))) + a.h.y() * std::abs(axis.dot(a.rot.col(1)));
      const double rb =
          b.h.x() * std::abs(axis.dot(b.rot.col(0))) + b.h.y() * std::abs(axis.dot(b.rot.col(1)));
      least = std::min(least, ra + rb + gap - std::abs(axis.dot(d)));
    }
  }
  return std::max(0.0, least);
}

}  // namespace

std::vector<Placement> scatter_placements(const std::vector<const ObjectType*>& types,
                                          const ScatterRegion& region, std::uint64_t seed) {
  core::Rng rng(seed);
  std::vector<Footprint> taken;
  std::vector<Placement> out;
  for (const ObjectType* t : types) {
    ensure(t != nullptr, "scatter: null object type");
    Placement best;
    best.name = t->name;
    double best_overlap = std::numeric_limits<double>::infinity();
    for (int attempt = 0; attempt < kScatterAttempts && best_overlap > 0; ++attempt) {
      const Eigen::Vector2d p(rng.uniform(region.min.x(), region.max.x()),
                              rng.uniform(region.min.y(), region.max.y()));
      const double yaw = rng.uniform(-std::numbers::pi, std::numbers::pi);
      const Footprint f = footprint(*t, p, yaw);
      const double r = f.h.norm();
      double o = std::max(0.0, region.base_clearance + r - f.c.norm()) +
                 std::max(0.0, f.c.norm() - region.max_radius);
      for (const Footprint& g : taken) o += overlap(f, g, region.gap);
      if (o < best_overlap) {
        best_overlap = o;
        best.position = p;
        best.yaw = yaw;
      }
    }
    if (best_overlap > 0) {
      spdlog::warn("scatter: no free place for '{}', it overlaps by {:.3f} m", t->name,
                   best_overlap);
    }
    taken.push_back(footprint(*t, best.position, best.yaw));
    out.push_back(best);
  }
  return out;
}

namespace {

// The objects of the table: given, or drawn without repetition from the catalogue.
std::vector<const ObjectType*> table_types(const TableOptions& options,
                                           const ObjectCatalogue& catalogue) {
  std::vector<const ObjectType*> types;
  if (!options.objects.empty()) {
    for (const std::string& n : options.objects) types.push_back(&catalogue.get(n));
    return types;
  }
  std::vector<std::string> pool = catalogue.names();
  core::Rng rng(options.seed ^ 0x7ab1eULL);
  require(static_cast<std::size_t>(options.object_count) <= pool.size(),
          "table: more objects than the catalogue has");
  for (int i = 0; i < options.object_count; ++i) {
    const auto k = static_cast<std::ptrdiff_t>(rng.index(pool.size()));
    types.push_back(&catalogue.get(pool[static_cast<std::size_t>(k)]));
    pool.erase(pool.begin() + k);
  }
  return types;
}

// The camera looks at the scatter region from the front (-y), above.
SceneDescription table_scene(const TableOptions& options,
                             const std::vector<const ObjectType*>& types,
                             const std::vector<Placement>& places) {
  SceneDescription scene = default_scene();
  scene.backdrop.enabled = false;
  CameraSpec& cam = scene.cameras.at(0);
  cam.width = options.width;
  cam.height = options.height;
  cam.position = {0.24, -0.40, 0.80};
  cam.target = {0.24, 0.02, 0.0};
  for (std::size_t i = 0; i < types.size(); ++i) {
    PlacedObject o;
    o.type = types[i]->name;
    o.name = types[i]->name;
    o.position = places[i].position;
    o.yaw = places[i].yaw;
    scene.objects.push_back(o);
  }
  scene.validate();
  return scene;
}

Pose resting_pose(const ObjectType& type, const Placement& p) {
  Pose pose = Pose::Identity();
  pose.translate(Eigen::Vector3d(p.position.x(), p.position.y(), type.bottom()));
  pose.rotate(Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()));
  return pose;
}

// Copies of the table's object types: the robot outlives the catalogue it was built from.
std::vector<ObjectType> copies(const std::vector<const ObjectType*>& types) {
  std::vector<ObjectType> out;
  out.reserve(types.size());
  for (const ObjectType* t : types) out.push_back(*t);
  return out;
}

std::vector<const ObjectType*> pointers(const std::vector<ObjectType>& types) {
  std::vector<const ObjectType*> out;
  out.reserve(types.size());
  for (const ObjectType& t : types) out.push_back(&t);
  return out;
}

}  // namespace

struct SimulatedRobot::State {
  State(const TableOptions& o, const ObjectCatalogue& catalogue)
      : options(o),
        owned(copies(table_types(o, catalogue))),
        types(pointers(owned)),
        world(
            World::build(table_scene(o, types, scatter_placements(types, {}, o.seed)), catalogue)),
        renderer(world, render_options(o)),
        camera_name(world.camera_names().at(0)),
        ik_state(world.arm()) {}

  static RenderOptions render_options(const TableOptions& o) {
    RenderOptions r;
    r.shadows = o.shadows;
    r.reflections = false;
    return r;
  }

  // Parks the arm turned away from the table (j1 near its limit, toward -x) and folded up, out
  // of the camera's view.
  void park() {
    robot::JointVector q;
    q << kParkJoints[0], kParkJoints[1], kParkJoints[2], kParkJoints[3], kParkJoints[4];
    world.set_arm_configuration(world.arm().clamp(q));
  }

  void settle() {
    for (int i = 0; i < kSettleSteps; ++i) world.step();
  }

  TableOptions options;
  std::vector<ObjectType> owned;  // never resized: `types` points into it
  std::vector<const ObjectType*> types;
  World world;
  Renderer renderer;
  std::string camera_name;
  robot::ArmState ik_state;
  std::vector<ObjectId> contacts;
};

SimulatedRobot::SimulatedRobot(const TableOptions& options, const ObjectCatalogue& catalogue) {
  options.validate();
  s_ = std::make_unique<State>(options, catalogue);
  s_->park();
  s_->settle();
}

SimulatedRobot::~SimulatedRobot() = default;

robot::Look SimulatedRobot::look() {
  robot::Look l;
  l.image = s_->renderer.rgb(s_->world, s_->camera_name);
  l.t = s_->world.time();
  l.q = s_->world.arm_joints();
  l.ee = s_->world.ee_position();
  l.camera = camera();
  // The arm's self-model: the sim draws its links exactly (the arm's id in the mask pass).
  l.arm_mask = ground_truth_mask() == kArmId;
  return l;
}

geometry::Camera SimulatedRobot::camera() const { return s_->world.camera(s_->camera_name); }
const robot::Arm& SimulatedRobot::arm() const { return s_->world.arm(); }
robot::JointVector SimulatedRobot::joints() const { return s_->world.arm_joints(); }

namespace {

std::optional<episode::EpisodeWriter> open_writer(const robot::PushRecording& rec,
                                                  const World& world, const geometry::Camera& cam,
                                                  std::uint64_t seed) {
  if (rec.episode_dir.empty()) return std::nullopt;
  if (fs::exists(rec.episode_dir) && !rec.overwrite) {
    throw Error(rec.episode_dir.string() + ": already exists (use --overwrite to replace it)");
  }
  episode::EpisodeInfo info;
  info.fps = rec.fps;
  info.width = cam.width;
  info.height = cam.height;
  info.arm_name = "proprio-sim-arm";
  info.joint_count = robot::kArmJoints;
  info.has_masks = false;
  info.provenance.run = rec.run;
  if (!info.provenance.run.seed) info.provenance.run.seed = seed;
  info.provenance.source = episode::Source::kSimulated;
  info.provenance.scenario = "robot-push";
  (void)world;
  episode::EpisodeWriterOptions wopt;
  wopt.overwrite = rec.overwrite;
  return std::optional<episode::EpisodeWriter>(std::in_place, rec.episode_dir, info, cam,
                                               std::vector<episode::ObjectInfo>{}, std::nullopt,
                                               wopt);
}

}  // namespace

robot::PushReport SimulatedRobot::push(const robot::TablePush& push,
                                       const robot::PushRecording& recording) {
  push.validate();
  require(std::isfinite(recording.fps) && recording.fps > 0 && recording.fps <= 500,
          "push: fps must be in (0, 500]");
  World& world = s_->world;
  robot::PushMotionOptions mopt;
  mopt.rate_hz = 1.0 / world.timestep();
  const robot::PushMotion motion =
      robot::plan_push_motion(s_->ik_state, push, world.arm_joints(), mopt);
  const geometry::Camera cam = camera();
  std::optional<episode::EpisodeWriter> writer =
      open_writer(recording, world, cam, s_->options.seed);
  const int steps_per_frame =
      std::max(1, static_cast<int>(std::lround(1.0 / (recording.fps * world.timestep()))));

  world.set_arm_configuration(motion.q_above_start);
  if (!world.objects_touched_by_arm().empty()) {
    // The transit is not simulated: an arm put into an object would throw it across the room.
    s_->park();
    world.forward();
    throw Error("push: the arm above the start (" + std::to_string(push.start.x()) + ", " +
                std::to_string(push.start.y()) + ") m would be inside an object; nothing moved");
  }
  robot::PushReport report;
  report.push = push;
  s_->contacts.clear();
  const double t0 = world.time();
  const int n = static_cast<int>(motion.joints.size()) + kSettleSteps;
  bool touched_since_frame = false;
  for (int k = 0; k < n; ++k) {
    const auto i =
        static_cast<std::size_t>(std::min(k, static_cast<int>(motion.joints.size()) - 1));
    world.set_arm_targets(motion.joints.q[i]);
    world.step();
    for (const ObjectId id : world.objects_touched_by_arm()) {
      touched_since_frame = true;
      if (std::find(s_->contacts.begin(), s_->contacts.end(), id) == s_->contacts.end()) {
        s_->contacts.push_back(id);
      }
    }
    if ((k + 1) % steps_per_frame == 0) {
      if (writer) {
        episode::ArmSample a;
        a.t = world.time() - t0;
        a.q = world.arm_joints();
        a.ee = world.ee_position();
        a.ee_image = cam.project(a.ee);
        a.touching = touched_since_frame;
        writer->add_frame(s_->renderer.rgb(world, s_->camera_name), a);
      }
      if (touched_since_frame && !report.first_touch_frame)
        report.first_touch_frame = report.frames;
      report.touched = report.touched || touched_since_frame;
      touched_since_frame = false;
      ++report.frames;
    }
  }
  std::sort(s_->contacts.begin(), s_->contacts.end());
  report.seconds = world.time() - t0;
  if (writer) {
    writer->finish();
    report.episode_dir = recording.episode_dir;
  }
  s_->park();
  s_->settle();
  report.message =
      report.touched ? "pushed; the arm touched an object" : "pushed; the arm touched nothing";
  return report;
}

std::vector<ObjectTruth> SimulatedRobot::ground_truth() const {
  std::vector<ObjectTruth> out;
  const World& world = s_->world;
  const Eigen::Vector2d lo = table_min();
  const Eigen::Vector2d hi = table_max();
  for (const SceneObject& o : world.objects()) {
    ObjectTruth t;
    t.id = o.id;
    t.name = o.type.name;
    const Pose pose = world.object_pose(o.id);
    t.position = pose.translation();
    t.centre = pose * o.type.center();
    const Eigen::Vector3d x_axis = pose.rotation().col(0);
    t.yaw = std::atan2(x_axis.y(), x_axis.x());
    t.footprint_radius = o.type.footprint_radius();
    t.upright = x_axis.z() > -0.5 && x_axis.z() < 0.5 && pose.rotation()(2, 2) > 0.7;
    t.on_table = t.position.z() > kFallenBelow && t.position.x() >= lo.x() &&
                 t.position.x() <= hi.x() && t.position.y() >= lo.y() && t.position.y() <= hi.y();
    out.push_back(t);
  }
  return out;
}

cv::Mat SimulatedRobot::ground_truth_mask() {
  return s_->renderer.mask(s_->world, s_->camera_name);
}

const std::vector<ObjectId>& SimulatedRobot::last_push_contacts() const { return s_->contacts; }

std::vector<Placement> SimulatedRobot::scatter(std::uint64_t seed) {
  std::vector<Placement> places = scatter_placements(s_->types, {}, seed);
  World& world = s_->world;
  for (std::size_t i = 0; i < places.size(); ++i) {
    const SceneObject& o = world.objects().at(i);
    world.set_object_pose(o.id, resting_pose(*s_->types[i], places[i]));
    spdlog::info("scatter (seed {}): {} at ({:.3f}, {:.3f}) m, yaw {:.2f} rad", seed,
                 places[i].name, places[i].position.x(), places[i].position.y(), places[i].yaw);
  }
  s_->park();
  s_->settle();
  return places;
}

Eigen::Vector2d SimulatedRobot::table_min() const {
  const TableSpec& t = s_->world.scene().description.table;
  return t.center - 0.5 * t.size;
}

Eigen::Vector2d SimulatedRobot::table_max() const {
  const TableSpec& t = s_->world.scene().description.table;
  return t.center + 0.5 * t.size;
}

// --- added for self-supervision's held-out views ---------------------------------------------

void SimulatedRobot::place(const std::vector<Placement>& places) {
  require(places.size() == s_->types.size(), "place: one place per object is needed");
  World& world = s_->world;
  for (std::size_t i = 0; i < places.size(); ++i) {
    world.set_object_pose(world.objects().at(i).id, resting_pose(*s_->types[i], places[i]));
  }
  s_->park();
  s_->settle();
}

}  // namespace proprio::sim
