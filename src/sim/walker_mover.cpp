#include "walker_mover.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "scripted_pose.hpp"

namespace proprio::sim {

namespace {

// The walkers' box: x well beyond the camera's view of the table (about -0.3..0.85 m at
// y = 0.3, computed from the camera below), so that they leave it and come back; y from behind
// the push corridor to the backdrop (y = 0.56).
constexpr double kWalkMinX = -0.55, kWalkMaxX = 1.05, kWalkMaxY = 0.54;
// The part of that box that the camera sees whole at every y (about -0.2..0.74 m at y = 0.15).
constexpr double kViewMinX = -0.1, kViewMaxX = 0.62;
constexpr double kWalkGap = 0.01;    // least distance between two walkers' footprints, m
constexpr double kBehindGap = 0.03;  // least distance, walker footprint to the target's, in y, m
// Placing: draws per walker, and rounds of the whole draw, before giving up.
constexpr int kPlaceAttempts = 200;
constexpr int kPlaceRounds = 50;
// Start speeds, m/s, and the range the walk keeps them in: slow enough to follow frame by frame.
constexpr double kMinStartSpeed = 0.06, kMaxStartSpeed = 0.16;
constexpr double kMinSpeed = 0.06, kMaxSpeed = 0.2;
// The random walk's drift per square root of a second (Brownian): heading and yaw, rad; speed,
// m/s. The yaw also turns steadily (kSpin, rad/s) so that the walkers show their sides.
constexpr double kHeadingDrift = 1.5;
constexpr double kSpeedDrift = 0.05;
constexpr double kYawDrift = 1.0;
constexpr double kSpin = 0.5;
// The walk's stream: the seed xor "WALK", so that it leaves the plan's draws alone.
constexpr std::uint64_t kWalkStream = 0x57414c4bULL;

}  // namespace

void plan_walkers(const RecordOptions& options, const ObjectCatalogue& catalogue, double target_r,
                  core::Rng& rng, ScenarioPlan& plan) {
  plan.walk_min = {options.scatter_in_view ? kViewMinX : kWalkMinX, 0.0};
  plan.walk_max = {options.scatter_in_view ? kViewMaxX : kWalkMaxX, kWalkMaxY};
  std::vector<ScenarioPlan::Walker> walkers;
  for (const std::string& name : options.scatter_objects) {
    if (name == options.object) continue;
    ScenarioPlan::Walker w;
    w.name = "scatter-" + name;
    w.radius = catalogue.get(name).footprint_radius();
    w.y_min = target_r + w.radius + kBehindGap;
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
  for (int round = 0; round < kPlaceRounds && !placed_all; ++round) {
    placed_all = true;
    for (std::size_t i = 0; i < walkers.size() && placed_all; ++i) {
      ScenarioPlan::Walker& w = walkers[i];
      bool placed = false;
      for (int attempt = 0; attempt < kPlaceAttempts && !placed; ++attempt) {
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
    w.speed = rng.uniform(kMinStartSpeed, kMaxStartSpeed);
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

WalkerMover::WalkerMover(const World& world, const ScenarioPlan& plan, std::uint64_t seed)
    : walkers_(plan.walkers),
      lo_(plan.walk_min),
      hi_(plan.walk_max),
      rng_(core::stream_seed(seed, kWalkStream)) {
  for (const auto& w : walkers_) ids_.push_back(world.object(w.name).id);
}

// Heading and speed drift, the walkers bounce off the box's walls and turn back from each other.
void WalkerMover::advance(double dt) {
  for (std::size_t i = 0; i < walkers_.size(); ++i) {
    ScenarioPlan::Walker& w = walkers_[i];
    w.heading += rng_.normal() * kHeadingDrift * std::sqrt(dt);
    w.speed =
        std::clamp(w.speed + rng_.normal() * kSpeedDrift * std::sqrt(dt), kMinSpeed, kMaxSpeed);
    w.yaw += rng_.normal() * kYawDrift * std::sqrt(dt) + kSpin * dt;
    Eigen::Vector2d p =
        w.position + w.speed * dt * Eigen::Vector2d(std::cos(w.heading), std::sin(w.heading));
    if (p.x() < lo_.x() || p.x() > hi_.x()) w.heading = std::numbers::pi - w.heading;
    if (p.y() < std::max(lo_.y(), w.y_min) || p.y() > hi_.y() - w.radius) w.heading = -w.heading;
    p = w.position + w.speed * dt * Eigen::Vector2d(std::cos(w.heading), std::sin(w.heading));
    bool blocked = p.x() < lo_.x() || p.x() > hi_.x() || p.y() < std::max(lo_.y(), w.y_min) ||
                   p.y() > hi_.y() - w.radius;
    for (std::size_t j = 0; j < walkers_.size() && !blocked; ++j) {
      if (j == i) continue;
      const double d = (p - walkers_[j].position).norm();
      // Only moves that bring two walkers closer are refused, so that two that touch part.
      blocked = d < w.radius + walkers_[j].radius + kWalkGap &&
                d < (w.position - walkers_[j].position).norm();
    }
    if (blocked) {
      w.heading += std::numbers::pi;
    } else {
      w.position = p;
    }
  }
}

void WalkerMover::move(World& world) const {
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    const ScenarioPlan::Walker& w = walkers_[i];
    world.set_object_pose(
        ids_[i], on_table(world.object(ids_[i]).type, w.position.x(), w.position.y(), w.yaw));
  }
}

}  // namespace proprio::sim
