#include "proprio/sim/simulated_robot.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "backdrop_video.hpp"
#include "distractor_mover.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxTableObjects = 8;
constexpr int kScatterAttempts = 400;   // places tried for one object in one draw
constexpr int kScatterRestarts = 60;    // whole draws tried before objects may overlap
constexpr int kSettleSteps = 150;       // physics steps for objects to come to rest (0.3 s)
constexpr double kFallenBelow = -0.01;  // m: an object's origin below the table top is off
// Where the arm waits between pushes, j1..j5 (rad): turned toward -x, upper arm raised, forearm
// and hand folded up.
constexpr std::array<double, robot::kArmJoints> kParkJoints{2.9, 0.3, 1.2, 1.0, 0.0};
// The shape the arm turns about its base in during a transit, j2..j4 (rad): upper arm, forearm
// and hand raised over the base (every link within 0.1 m of the base's axis and above the
// shoulder, 0.2 m), clear of the objects on the table (at least 0.1 m from the axis plus their
// radius).
constexpr std::array<double, 3> kRaisedJoints{1.3, 0.5, 0.5};
// The distractors are put back on their script this often, physics steps (and before a render).
constexpr int kDistractorEvery = 10;
// Distractors: catalogue objects of at most this footprint radius, m, are taken first (larger
// ones when too few are left): the backdrop stands behind the largest.
constexpr double kMaxDistractorRadius = 0.11;
constexpr double kDistractorClearance = 0.01;
// The backdrop stands behind a distractor of at least this radius, m (so a little behind the
// scatter region when there are none).
constexpr double kLeastDistractorRadius = 0.05;
// The transit: the fastest mean joint speed of a segment, rad/s (smoothstep profile: its peak is
// 1.5 times that), the shortest segment, s, and the arm's rest above the start before lowering, s.
constexpr double kTransitJointSpeed = 1.2;
constexpr double kShortestSegment = 0.25;
constexpr double kTransitHold = 0.1;
// The transit's way down to the push's start and up from its end: speed, m/s, and the distance
// between inverse-kinematics solutions on it, m.
constexpr double kVerticalSpeed = 0.15;
constexpr double kVerticalStep = 0.01;
// Where the transit height is out of reach, these lower ones are tried, m.
constexpr double kLowerTransit = 0.22;
constexpr double kLowestTransit = 0.18;
// Poses of the transit checked for contact before the arm moves: every this many samples.
constexpr int kTransitCheckEvery = 5;
// How far the lifted hand backs away along the push before going back, when it still touches
// the pushed object (one taller than the lift), m: the first that frees it.
constexpr std::array<double, 3> kRetreatSteps{0.02, 0.04, 0.07};

// The backdrop of the robot's table: a wall behind the scatter region (ScatterRegion: y <= 0.30)
// seen at the top of the camera's view (the camera looks down steeply: the table's far edge,
// y = 0.5, is at the image's top), and the distractors' line in front of it, beyond the scatter
// region by the largest distractor's footprint radius `radius` (m) and a clearance; the wall
// stands that far behind the line.
BackdropLayout robot_backdrop_layout(double radius) {
  BackdropLayout l;
  l.line_y = ScatterRegion{}.max.y() + radius + kDistractorClearance;
  l.center = {0.24, l.line_y + radius + kDistractorClearance, 0.35};
  l.size = {1.6, 0.7};
  l.centre_x = 0.24;
  l.amplitude = 0.34;
  l.ghost_distractors = true;
  return l;
}

bool is_count(const std::string& s) {
  return !s.empty() && s.size() <= 2 &&
         std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// "a, b,c" -> {"a", "b", "c"}; throws Error for an empty name.
std::vector<std::string> name_list(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  const auto flush = [&] {
    const auto b = cur.find_first_not_of(" \t");
    const auto e = cur.find_last_not_of(" \t");
    require(b != std::string::npos, "table: clutter: an empty name in '" + s + "'");
    out.push_back(cur.substr(b, e - b + 1));
    cur.clear();
  };
  for (const char c : s) {
    if (c == ',') {
      flush();
    } else {
      cur += c;
    }
  }
  flush();
  return out;
}

}  // namespace

void TableOptions::validate() const {
  core::check_field_bounds(*this, "table");
  require(objects.size() <= static_cast<std::size_t>(kMaxTableObjects), "table: at most 8 objects");
  if (is_count(clutter)) {
    const int n = std::stoi(clutter);
    const int own = objects.empty() ? object_count : static_cast<int>(objects.size());
    require(own + n <= kMaxTableObjects, "table: at most 8 objects and clutter together");
  } else if (!clutter.empty()) {
    const std::size_t own =
        objects.empty() ? static_cast<std::size_t>(object_count) : objects.size();
    require(own + name_list(clutter).size() <= static_cast<std::size_t>(kMaxTableObjects),
            "table: at most 8 objects and clutter together");
  }
  if (background == Background::kPhoto) {
    require(std::filesystem::is_regular_file(background_photo),
            background_photo.string() + ": no such background photograph");
  }
  if (background == Background::kMoving) {
    require(std::filesystem::is_regular_file(background_video),
            background_video.string() + ": no such background video");
  }
}

int TableOptions::distractor_count() const {
  if (distractors >= 0) return distractors;
  return background == Background::kMoving ? 2 : 0;
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

Footprint footprint(const BoxFootprint& b) {
  Footprint f;
  f.rot = Eigen::Rotation2Dd(b.yaw).toRotationMatrix();
  f.c = b.centre;
  f.h = b.half;
  return f;
}

}  // namespace

BoxFootprint box_footprint(const ObjectTruth& truth, const ObjectType& type) {
  BoxFootprint b;
  b.centre = truth.centre.head<2>();
  b.half = type.half_extents().head<2>();
  b.yaw = truth.yaw;
  return b;
}

double footprint_overlap(const BoxFootprint& a, const BoxFootprint& b, double gap) {
  require(std::isfinite(gap) && gap >= 0, "footprint_overlap: gap must be finite and >= 0");
  return overlap(footprint(a), footprint(b), gap);
}

namespace {

// One draw of the scatter: each type (in `order`) at the best of kScatterAttempts random places
// given the ones placed before it. Returns the summed overlap (0: every object has room).
double scatter_once(const std::vector<const ObjectType*>& types,
                    const std::vector<std::size_t>& order, const ScatterRegion& region,
                    core::Rng& rng, std::vector<Placement>& out) {
  std::vector<Footprint> taken;
  out.assign(types.size(), Placement{});
  double total = 0;
  for (const std::size_t i : order) {
    const ObjectType* t = types[i];
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
    total += best_overlap;
    taken.push_back(footprint(*t, best.position, best.yaw));
    out[i] = best;
  }
  return total;
}

}  // namespace

std::vector<Placement> scatter_placements(const std::vector<const ObjectType*>& types,
                                          const ScatterRegion& region, std::uint64_t seed) {
  for (const ObjectType* t : types) ensure(t != nullptr, "scatter: null object type");
  core::Rng rng(seed);
  // The largest footprints first (a table is filled as a person would: the big things, then
  // the small ones in the gaps); ties keep the given order.
  std::vector<std::size_t> order(types.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Eigen::Vector3d ha = types[a]->half_extents();
    const Eigen::Vector3d hb = types[b]->half_extents();
    return ha.x() * ha.y() > hb.x() * hb.y();
  });
  // A draw in which some object found no room is drawn again as a whole (from the same stream),
  // up to kScatterRestarts times; the least-overlapping draw is kept.
  std::vector<Placement> best;
  double best_total = std::numeric_limits<double>::infinity();
  std::vector<Placement> draw;
  for (int restart = 0; restart < kScatterRestarts && best_total > 0; ++restart) {
    const double total = scatter_once(types, order, region, rng, draw);
    if (total < best_total) {
      best_total = total;
      best = draw;
    }
  }
  if (best_total > 0) {
    spdlog::warn("scatter: no draw of {} gave every object room; they overlap by {:.3f} m",
                 kScatterRestarts, best_total);
  }
  return best;
}

namespace {

// Draws `n` names from `pool` without repetition (removing them from it).
std::vector<std::string> draw(std::vector<std::string>& pool, int n, core::Rng& rng,
                              const char* what) {
  require(static_cast<std::size_t>(n) <= pool.size(),
          std::string("table: not enough catalogue objects for the ") + what);
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::ptrdiff_t>(rng.index(pool.size()));
    out.push_back(pool[static_cast<std::size_t>(k)]);
    pool.erase(pool.begin() + k);
  }
  return out;
}

void remove_from(std::vector<std::string>& pool, const std::vector<std::string>& names) {
  for (const std::string& n : names) std::erase(pool, n);
}

// The table's catalogue names: the objects (given, or drawn without repetition from the
// catalogue), the clutter (given, or drawn from the rest) and the distractors (drawn from the
// rest that is small enough).
struct TableNames {
  std::vector<std::string> objects, clutter, distractors;
  BackdropLayout layout;  // the backdrop behind the largest distractor
};

TableNames table_names(const TableOptions& options, const ObjectCatalogue& catalogue) {
  TableNames t;
  if (!options.objects.empty()) {
    for (const std::string& n : options.objects) (void)catalogue.get(n);
    t.objects = options.objects;
  } else {
    std::vector<std::string> pool = catalogue.names();
    auto rng = core::Rng::stream(options.seed, 0x7ab1eULL);
    t.objects = draw(pool, options.object_count, rng, "objects");
  }
  std::vector<std::string> pool = catalogue.names();
  remove_from(pool, t.objects);
  if (is_count(options.clutter)) {
    auto rng = core::Rng::stream(options.seed, 0xc1a77e7ULL);
    t.clutter = draw(pool, std::stoi(options.clutter), rng, "clutter");
  } else if (!options.clutter.empty()) {
    t.clutter = name_list(options.clutter);
    for (const std::string& n : t.clutter) {
      (void)catalogue.get(n);
      require(std::find(pool.begin(), pool.end(), n) != pool.end(),
              "table: clutter '" + n + "' is on the table already (an object or clutter twice)");
      std::erase(pool, n);
    }
  }
  remove_from(pool, t.clutter);
  // Small distractors first (they keep the backdrop near); larger ones when too few are left.
  std::vector<std::string> large = pool;
  std::erase_if(pool, [&](const std::string& n) {
    return catalogue.get(n).footprint_radius() > kMaxDistractorRadius;
  });
  remove_from(large, pool);
  auto rng = core::Rng::stream(options.seed, 0xd15ac7ULL);
  const int small = std::min(options.distractor_count(), static_cast<int>(pool.size()));
  t.distractors = draw(pool, small, rng, "distractors");
  for (const std::string& n : draw(large, options.distractor_count() - small, rng, "distractors")) {
    t.distractors.push_back(n);
  }
  double radius = kLeastDistractorRadius;
  for (const std::string& n : t.distractors) {
    radius = std::max(radius, catalogue.get(n).footprint_radius());
  }
  t.layout = robot_backdrop_layout(radius);
  return t;
}

std::vector<const ObjectType*> types_of(const std::vector<std::string>& a,
                                        const std::vector<std::string>& b,
                                        const ObjectCatalogue& catalogue) {
  std::vector<const ObjectType*> types;
  for (const auto* v : {&a, &b}) {
    for (const std::string& n : *v) types.push_back(&catalogue.get(n));
  }
  return types;
}

// The camera looks at the scatter region from the front (-y), above; the backdrop and the
// distractors (after the objects and the clutter) as the options say.
SceneDescription table_scene(const TableOptions& options,
                             const std::vector<const ObjectType*>& types,
                             const std::vector<Placement>& places,
                             const std::vector<std::string>& distractors,
                             const BackdropLayout& layout) {
  SceneDescription scene = default_scene();
  set_backdrop(scene, options.background, layout, options.background_photo);
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
  for (std::size_t i = 0; i < distractors.size(); ++i) {
    scene.objects.push_back(distractor_start(distractors[i], static_cast<int>(i), layout));
  }
  scene.validate();
  return scene;
}

std::vector<std::string> distractor_instances(const std::vector<std::string>& types) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < types.size(); ++i) {
    out.push_back(distractor_start(types[i], static_cast<int>(i)).name);
  }
  return out;
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

// A joint-space move from a to b, one sample per `dt`, smoothstep in time (no jump of speed at
// either end), at most kTransitJointSpeed on average for the joint that moves most.
std::vector<robot::JointVector> joint_segment(const robot::JointVector& a,
                                              const robot::JointVector& b, double dt) {
  const double longest = (b - a).cwiseAbs().maxCoeff();
  const double duration = std::max(kShortestSegment, longest / kTransitJointSpeed);
  const int n = std::max(1, static_cast<int>(std::lround(duration / dt)));
  std::vector<robot::JointVector> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int k = 1; k <= n; ++k) {
    const double u = static_cast<double>(k) / n;
    const double w = u * u * (3.0 - 2.0 * u);
    out.emplace_back(a + w * (b - a));
  }
  return out;
}

}  // namespace

struct SimulatedRobot::State {
  State(const TableOptions& o, const ObjectCatalogue& catalogue, const TableNames& names)
      : options(o),
        owned(copies(types_of(names.objects, names.clutter, catalogue))),
        types(pointers(owned)),
        object_count(names.objects.size()),
        world(World::build(table_scene(o, types, scatter_placements(types, {}, o.seed),
                                       names.distractors, names.layout),
                           catalogue)),
        renderer(world, render_options(o)),
        camera_name(world.camera_names().at(0)),
        ik_state(world.arm()),
        video(o.background == Background::kMoving, o.background_video),
        distractors(world, distractor_instances(names.distractors), names.layout) {}

  static RenderOptions render_options(const TableOptions& o) {
    RenderOptions r;
    r.shadows = o.shadows;
    r.reflections = false;
    return r;
  }

  [[nodiscard]] static robot::JointVector park_joints() {
    robot::JointVector q;
    q << kParkJoints[0], kParkJoints[1], kParkJoints[2], kParkJoints[3], kParkJoints[4];
    return q;
  }

  // Parks the arm at once turned away from the table (j1 near its limit, toward -x) and folded
  // up, out of the camera's view (at the start, and when a person re-scatters the table).
  void park() { world.set_arm_configuration(world.arm().clamp(park_joints())); }

  // One physics step; the distractors are put back on their script every kDistractorEvery.
  void step() {
    world.step();
    if (!distractors.ids().empty() && ++since_distractors >= kDistractorEvery) {
      distractors.move(world, world.time());
      since_distractors = 0;
    }
  }

  void settle() {
    for (int i = 0; i < kSettleSteps; ++i) step();
  }

  // The moving background at the robot's time: distractors where their script puts them now,
  // the video's frame of now. Before every render.
  void show_now() {
    if (!distractors.ids().empty()) distractors.move(world, world.time());
    video.show_at(world, renderer, world.time());
  }

  // The transit from `from` (the park) to `to` through joint interpolation: raised over the
  // base, turned toward `xy`, unfolded to the transit height above it, straight down to `to`;
  // back to the park (`outward` false) the reverse way from `from`. Samples at the physics rate.
  std::vector<robot::JointVector> transit(const robot::JointVector& from,
                                          const robot::JointVector& to, const Eigen::Vector2d& xy,
                                          bool outward) {
    const robot::JointVector arm_end = outward ? to : from;
    // The transit height, or lower where the arm cannot reach that high (far from its base).
    robot::JointVector high = arm_end;
    for (const double h : {options.transit_height, kLowerTransit, kLowestTransit}) {
      try {
        high = robot::solve_ik(ik_state, Eigen::Vector3d(xy.x(), xy.y(), h), arm_end).q;
        break;
      } catch (const Error&) {
        if (h == kLowestTransit) throw;
      }
    }
    const robot::JointVector park_q = world.arm().clamp(park_joints());
    robot::JointVector raised_park = park_q;
    for (int j = 0; j < 3; ++j) raised_park[j + 1] = kRaisedJoints[static_cast<std::size_t>(j)];
    raised_park = world.arm().clamp(raised_park);
    robot::JointVector raised = raised_park;
    raised[0] = high[0];
    const double dt = world.timestep();
    std::vector<robot::JointVector> out;
    const auto append = [&out](const std::vector<robot::JointVector>& part) {
      out.insert(out.end(), part.begin(), part.end());
    };
    if (outward) {
      if ((from - park_q).cwiseAbs().maxCoeff() > 1e-6) {
        append(joint_segment(from, raised, dt));  // not at the park: raised first
      } else {
        append(joint_segment(from, raised_park, dt));
        append(joint_segment(raised_park, raised, dt));
      }
      append(joint_segment(raised, high, dt));
      append(vertical(high, to, dt));
    } else {
      append(vertical(from, high, dt));
      append(joint_segment(high, raised, dt));
      append(joint_segment(raised, raised_park, dt));
      append(joint_segment(raised_park, park_q, dt));
    }
    return out;
  }

  // The pusher tip straight up or down from where `a` puts it to the height `b` puts it at
  // (the same x y), kVerticalSpeed on average, smoothstep in time: joint interpolation between
  // inverse-kinematics solutions every kVerticalStep.
  std::vector<robot::JointVector> vertical(const robot::JointVector& a, const robot::JointVector& b,
                                           double dt) {
    const Eigen::Vector3d pa = ik_state.ee_position(a);
    const Eigen::Vector3d pb = ik_state.ee_position(b);
    const int m =
        std::max(1, static_cast<int>(std::ceil(std::abs(pb.z() - pa.z()) / kVerticalStep)));
    std::vector<robot::JointVector> way{a};
    for (int i = 1; i < m; ++i) {
      const Eigen::Vector3d p = pa + (pb - pa) * (static_cast<double>(i) / m);
      way.push_back(robot::solve_ik(ik_state, p, way.back()).q);
    }
    way.push_back(b);
    const double duration = std::max(kShortestSegment, (pb - pa).norm() / kVerticalSpeed);
    const int n = std::max(1, static_cast<int>(std::lround(duration / dt)));
    std::vector<robot::JointVector> out;
    for (int k = 1; k <= n; ++k) {
      const double u = static_cast<double>(k) / n;
      const double at = u * u * (3.0 - 2.0 * u) * m;
      const int i = std::min(static_cast<int>(at), m - 1);
      const double f = at - i;
      const auto iu = static_cast<std::size_t>(i);
      out.emplace_back(way[iu] + f * (way[iu + 1] - way[iu]));
    }
    return out;
  }

  // The way back from `lifted` (the hand lifted after a push that still touches an object) that
  // first backs the pusher away along `away` (table x y, any length) at its height, by the
  // first of kRetreatSteps whose pose and onward transit meet no object; none when every one
  // does or cannot be reached.
  std::optional<std::vector<robot::JointVector>> retreat(const robot::JointVector& lifted,
                                                         const Eigen::Vector2d& away) {
    if (away.norm() < 1e-9) return std::nullopt;
    const Eigen::Vector3d tip = ik_state.ee_position(lifted);
    const Eigen::Vector2d u = away.normalized();
    for (const double d : kRetreatSteps) {
      const Eigen::Vector3d p(tip.x() + d * u.x(), tip.y() + d * u.y(), tip.z());
      robot::JointVector q;
      try {
        q = robot::solve_ik(ik_state, p, lifted).q;
      } catch (const Error&) {
        continue;
      }
      std::vector<robot::JointVector> way;
      try {
        way = transit(q, q, p.head<2>(), false);
      } catch (const Error&) {
        continue;
      }
      if (path_meets_object({q}, lifted) || path_meets_object(way, lifted)) continue;
      std::vector<robot::JointVector> out = vertical(lifted, q, world.timestep());
      out.insert(out.end(), way.begin(), way.end());
      return out;
    }
    return std::nullopt;
  }

  // The objects the arm's moving links touch now. An object resting against the arm's base or
  // its first link (a cylinder turning on its own axis) is in the same contact at every pose:
  // no path can keep clear of it, and no transit sweeps it, so it does not count.
  std::vector<ObjectId> objects_met_by_moving_arm(std::string* part = nullptr) const {
    const mjModel& m = world.model();
    const mjData& d = world.data();
    const robot::Arm& a = world.arm();
    const int base = a.base_body();
    const int first = m.jnt_bodyid[a.joint_id(0)];
    std::vector<ObjectId> out;
    for (int i = 0; i < d.ncon; ++i) {
      const mjContact& c = d.contact[i];
      const std::array<int, 2> g{c.geom1, c.geom2};
      for (int k = 0; k < 2; ++k) {
        const int arm_geom = g[static_cast<std::size_t>(k)];
        const int other = g[static_cast<std::size_t>(1 - k)];
        if (world.geom_object_id(arm_geom) != kArmId) continue;
        const ObjectId id = world.geom_object_id(other);
        if (id == kArmId || id == kBackgroundId) continue;
        const int body = m.geom_bodyid[arm_geom];
        if (body == base || body == first) continue;
        if (part != nullptr && out.empty()) {
          const char* name = mj_id2name(&m, mjOBJ_GEOM, arm_geom);
          *part = name != nullptr ? name : "the arm";
        }
        out.push_back(id);
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // Whether the arm put at any sample of `path` (every kTransitCheckEvery-th and the last)
  // would touch an object (`met`: the first one's name and the sample's share of the path); the
  // arm is back at `current` after.
  // With `leaving`, the objects the arm touches at path[0] do not count while the arm is still
  // touching only them (moving away from an object it rests against); once it is clear of them,
  // any contact counts.
  bool path_meets_object(const std::vector<robot::JointVector>& path,
                         const robot::JointVector& current, std::string* met = nullptr,
                         bool leaving = false) {
    bool meets = false;
    std::vector<ObjectId> resting;
    if (leaving && !path.empty()) {
      world.set_arm_configuration(path.front());
      resting = objects_met_by_moving_arm();
    }
    for (std::size_t k = 0; k < path.size() && !meets; ++k) {
      if (k % kTransitCheckEvery != 0 && k + 1 != path.size()) continue;
      world.set_arm_configuration(path[k]);
      std::string part;
      const std::vector<ObjectId> touched = objects_met_by_moving_arm(&part);
      if (!resting.empty()) {
        const bool only_resting = std::all_of(touched.begin(), touched.end(), [&](ObjectId id) {
          return std::find(resting.begin(), resting.end(), id) != resting.end();
        });
        if (only_resting && !touched.empty()) continue;
        if (touched.empty()) resting.clear();  // clear of them: from here on everything counts
      }
      meets = !touched.empty();
      if (meets && met != nullptr) {
        *met = world.object(touched.front()).name + " (by " + part + ") at " +
               std::to_string(static_cast<int>(100.0 * static_cast<double>(k) /
                                               static_cast<double>(path.size()))) +
               "% of the way";
      }
    }
    world.set_arm_configuration(current);
    return meets;
  }

  // The arm's part of each geom (arm_part_name; empty: not the arm's), filled on first use.
  const std::string& part_of_geom(int geom) {
    if (geom_parts.empty()) {
      const mjModel& m = world.model();
      geom_parts.resize(static_cast<std::size_t>(m.ngeom));
      for (int g = 0; g < m.ngeom; ++g) {
        if (world.geom_object_id(g) != kArmId) continue;
        const char* name = mj_id2name(&m, mjOBJ_GEOM, g);
        geom_parts[static_cast<std::size_t>(g)] = arm_part_name(name != nullptr ? name : "");
      }
    }
    return geom_parts.at(static_cast<std::size_t>(geom));
  }

  // A table object (an object or clutter, not a distractor, the arm or the table).
  [[nodiscard]] bool is_table_object(ObjectId id) const {
    return id != kBackgroundId && id != kArmId && static_cast<std::size_t>(id) <= types.size();
  }

  // The pairs of table objects in contact now (a < b, ascending, once each).
  [[nodiscard]] std::vector<std::pair<ObjectId, ObjectId>> object_pairs_touching() const {
    const mjData& d = world.data();
    std::vector<std::pair<ObjectId, ObjectId>> out;
    for (int i = 0; i < d.ncon; ++i) {
      const ObjectId a = world.geom_object_id(d.contact[i].geom1);
      const ObjectId b = world.geom_object_id(d.contact[i].geom2);
      if (a == b || !is_table_object(a) || !is_table_object(b)) continue;
      out.emplace_back(std::min(a, b), std::max(a, b));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // Ground truth of the push so far: the arm's parts touching each object (contact_phases) and
  // the pairs of objects in contact (`resting`: those touching when it began).
  void note_contacts(ContactPhase phase,
                     const std::vector<std::pair<ObjectId, ObjectId>>& resting) {
    const mjData& d = world.data();
    for (int i = 0; i < d.ncon; ++i) {
      const std::array<int, 2> g{d.contact[i].geom1, d.contact[i].geom2};
      for (int k = 0; k < 2; ++k) {
        const int arm_geom = g[static_cast<std::size_t>(k)];
        const ObjectId other = world.geom_object_id(g[static_cast<std::size_t>(1 - k)]);
        if (world.geom_object_id(arm_geom) != kArmId || !is_table_object(other)) continue;
        const std::string& part = part_of_geom(arm_geom);
        for (ArmContact& c : contact_phases) {
          if (c.id == other && std::find(c.parts.begin(), c.parts.end(), part) == c.parts.end()) {
            c.parts.push_back(part);
          }
        }
      }
    }
    for (const std::pair<ObjectId, ObjectId>& ab : object_pairs_touching()) {
      const bool known =
          std::any_of(object_contacts.begin(), object_contacts.end(),
                      [&](const ObjectContact& c) { return c.a == ab.first && c.b == ab.second; });
      if (!known) {
        object_contacts.push_back(
            {ab.first, ab.second, phase, std::binary_search(resting.begin(), resting.end(), ab)});
      }
    }
  }

  TableOptions options;
  std::vector<ObjectType> owned;         // never resized: `types` points into it
  std::vector<const ObjectType*> types;  // objects, then clutter
  std::size_t object_count = 0;          // the first object_count of `types` are the objects
  World world;
  Renderer renderer;
  std::string camera_name;
  robot::ArmState ik_state;
  BackdropVideo video;
  DistractorMover distractors;
  int since_distractors = 0;
  std::vector<ObjectId> contacts;
  std::vector<ArmContact> contact_phases;
  std::vector<ObjectContact> object_contacts;
  std::vector<std::string> geom_parts;  // part_of_geom's table
};

SimulatedRobot::SimulatedRobot(const TableOptions& options, const ObjectCatalogue& catalogue) {
  options.validate();
  s_ = std::make_unique<State>(options, catalogue, table_names(options, catalogue));
  s_->park();
  s_->settle();
}

SimulatedRobot::~SimulatedRobot() = default;

robot::Look SimulatedRobot::look() {
  robot::Look l;
  s_->show_now();
  if (s_->options.depth) {
    Frame f = s_->renderer.render(s_->world, s_->camera_name, kPassRgb | kPassDepth);
    l.image = std::move(f.rgb);
    l.depth = std::move(f.depth);
  } else {
    l.image = s_->renderer.rgb(s_->world, s_->camera_name);
  }
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
                                                  const geometry::Camera& cam, std::uint64_t seed,
                                                  const std::vector<episode::ObjectInfo>& masks) {
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
  info.has_masks = !masks.empty();
  info.provenance.run = rec.run;
  if (!info.provenance.run.seed) info.provenance.run.seed = seed;
  info.provenance.source = episode::Source::kSimulated;
  info.provenance.scenario = "robot-push";
  episode::EpisodeWriterOptions wopt;
  wopt.overwrite = rec.overwrite;
  return std::optional<episode::EpisodeWriter>(std::in_place, rec.episode_dir, info, cam, masks,
                                               std::nullopt, wopt);
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
  mopt.roll_across = s_->options.roll_across;
  const robot::JointVector q_now = world.arm_joints();
  const robot::PushMotion motion = robot::plan_push_motion(s_->ik_state, push, q_now, mopt);
  const std::vector<robot::JointVector> out_path =
      s_->transit(q_now, motion.q_above_start, push.start, true);
  std::string met_out;
  if (s_->path_meets_object(out_path, q_now, &met_out, /*leaving=*/true)) {
    std::string m = "push: the arm's transit to above the start (";
    m += std::to_string(push.start.x());
    m += ", ";
    m += std::to_string(push.start.y());
    m += ") m would meet an object (";
    m += met_out;
    m += "); nothing moved";
    throw Error(m);
  }
  const geometry::Camera cam = camera();
  // Ground-truth masks only when asked for (TableOptions::record_masks: scoring oracles).
  std::vector<episode::ObjectInfo> mask_objects;
  if (s_->options.record_masks) {
    for (const ObjectTruth& o : ground_truth()) {
      mask_objects.push_back({o.id, o.name,
                              o.role == TableRole::kDistractor ? episode::ObjectRole::kDistractor
                                                               : episode::ObjectRole::kObject});
    }
    mask_objects.push_back({kArmId, "arm", episode::ObjectRole::kArm});
  }
  std::optional<episode::EpisodeWriter> writer =
      open_writer(recording, cam, s_->options.seed, mask_objects);
  const int steps_per_frame =
      std::max(1, static_cast<int>(std::lround(1.0 / (recording.fps * world.timestep()))));

  robot::PushReport report;
  report.push = push;
  s_->contacts.clear();
  s_->contact_phases.clear();
  s_->object_contacts.clear();
  const std::vector<std::pair<ObjectId, ObjectId>> resting = s_->object_pairs_touching();
  ContactPhase phase = ContactPhase::kTransit;
  const double t0 = world.time();
  double t_record = t0;
  bool touched_since_frame = false;
  int recorded_steps = 0;
  // One physics step toward q; the contacts; a frame every steps_per_frame recorded steps.
  const auto advance = [&](const robot::JointVector& q, bool recorded) {
    world.set_arm_targets(q);
    s_->step();
    for (const ObjectId id : world.objects_touched_by_arm()) {
      touched_since_frame = touched_since_frame || recorded;
      if (std::find(s_->contacts.begin(), s_->contacts.end(), id) == s_->contacts.end()) {
        s_->contacts.push_back(id);
        s_->contact_phases.push_back({id, phase, {}});
      }
    }
    s_->note_contacts(phase, resting);
    if (!recorded) return;
    if (recorded_steps == 0) t_record = world.time() - world.timestep();
    if (++recorded_steps % steps_per_frame != 0) return;
    if (writer) {
      s_->show_now();
      episode::ArmSample a;
      a.t = world.time() - t_record;
      a.q = world.arm_joints();
      a.ee = world.ee_position();
      a.ee_image = cam.project(a.ee);
      a.touching = touched_since_frame;
      episode::FrameExtras extras;
      if (!mask_objects.empty()) extras.mask = s_->renderer.mask(world, s_->camera_name);
      writer->add_frame(s_->renderer.rgb(world, s_->camera_name), a, extras);
    }
    if (touched_since_frame && !report.first_touch_frame) report.first_touch_frame = report.frames;
    report.touched = report.touched || touched_since_frame;
    touched_since_frame = false;
    ++report.frames;
  };

  // The transit to above the start, and a rest there for the controller to catch up.
  for (const auto& q : out_path) advance(q, s_->options.record_transit);
  const int hold = static_cast<int>(std::lround(kTransitHold / world.timestep()));
  for (int k = 0; k < hold; ++k) advance(motion.q_above_start, s_->options.record_transit);
  // Lower, push, lift, and the objects come to rest (recorded).
  phase = ContactPhase::kPush;
  const int n = static_cast<int>(motion.joints.size()) + kSettleSteps;
  for (int k = 0; k < n; ++k) {
    const auto i =
        static_cast<std::size_t>(std::min(k, static_cast<int>(motion.joints.size()) - 1));
    advance(motion.joints.q[i], true);
  }
  if (writer) {
    writer->finish();
    report.episode_dir = recording.episode_dir;
  }
  // Back to the park (not recorded). When the lifted hand still touches the pushed object (one
  // taller than the lift, pressed against the hand), it first backs away along the push, at
  // its height, by kRetreatSteps; where the way back still meets an object (one the push left
  // near the arm's base), the arm is put at the park at once, logged.
  phase = ContactPhase::kReturn;
  const robot::JointVector q_lifted = world.arm_joints();
  std::vector<robot::JointVector> back = s_->transit(q_lifted, q_lifted, push.end, false);
  std::string met;
  if (s_->path_meets_object(back, q_lifted, &met)) {
    std::optional<std::vector<robot::JointVector>> retreat =
        s_->retreat(q_lifted, push.start - push.end);
    if (retreat) {
      back = std::move(*retreat);
      met.clear();
      report.backed_away = true;
    }
  }
  if (!met.empty()) {
    report.parked_at_once = true;
    spdlog::warn("push: the arm's way back to the park would meet an object ({}); it is put there",
                 met);
    for (int k = 0; k < hold; ++k) advance(motion.joints.q.back(), false);
    s_->park();
  } else {
    for (const auto& q : back) advance(q, false);
    for (int k = 0; k < hold; ++k) advance(State::park_joints(), false);
  }
  std::sort(s_->contacts.begin(), s_->contacts.end());
  report.seconds = world.time() - t0;
  report.message =
      report.touched ? "pushed; the arm touched an object" : "pushed; the arm touched nothing";
  return report;
}

std::vector<ObjectTruth> SimulatedRobot::ground_truth() const {
  std::vector<ObjectTruth> out;
  const World& world = s_->world;
  const Eigen::Vector2d lo = table_min();
  const Eigen::Vector2d hi = table_max();
  const std::size_t n_table = s_->types.size();
  for (const SceneObject& o : world.objects()) {
    ObjectTruth t;
    const auto index = static_cast<std::size_t>(o.id - 1);
    t.role = index < s_->object_count ? TableRole::kObject
             : index < n_table        ? TableRole::kClutter
                                      : TableRole::kDistractor;
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
  s_->show_now();
  return s_->renderer.mask(s_->world, s_->camera_name);
}

const std::vector<ObjectId>& SimulatedRobot::last_push_contacts() const { return s_->contacts; }
const std::vector<ArmContact>& SimulatedRobot::last_push_contact_phases() const {
  return s_->contact_phases;
}
const std::vector<ObjectContact>& SimulatedRobot::last_push_object_contacts() const {
  return s_->object_contacts;
}

std::string arm_part_name(const std::string& geom_name) {
  if (geom_name == "arm_pusher") return "pusher";
  if (geom_name.starts_with("arm_finger_")) return "jaws";
  if (geom_name == "arm_palm") return "palm";
  return "links";
}

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
  ensure(places.size() == s_->types.size() || places.size() == s_->world.objects().size(),
         "place: one place per object (and clutter) is needed");
  World& world = s_->world;
  for (std::size_t i = 0; i < s_->types.size(); ++i) {
    world.set_object_pose(world.objects().at(i).id, resting_pose(*s_->types[i], places[i]));
  }
  s_->park();
  s_->settle();
}

void SimulatedRobot::wait(double seconds) {
  require(std::isfinite(seconds) && seconds >= 0 && seconds <= 3600,
          "wait: the time must be in [0, 3600] s");
  const auto steps = static_cast<long>(std::lround(seconds / s_->world.timestep()));
  for (long k = 0; k < steps; ++k) s_->step();
}

void SimulatedRobot::hold_still(double seconds) {
  require(std::isfinite(seconds) && seconds >= 0 && seconds <= 10,
          "hold_still: the time must be in [0, 10] s");
  // The actuators keep their targets while wait() steps the world: the arm stays where its last
  // motion left it, the distractors keep to their script, the next look shows the video's time.
  wait(seconds);
}

double SimulatedRobot::time() const { return s_->world.time(); }

}  // namespace proprio::sim
