#include "slider_mover.hpp"

#include <cmath>

#include "scripted_pose.hpp"

namespace proprio::sim {

namespace {

// The rows, m: y = kFirstRowY + kRowStep * index, behind the push corridor.
constexpr double kFirstRowY = 0.2;
constexpr double kRowStep = 0.06;
// The stretch of x they slide over and wrap round, m: wider than the camera's view of the table.
constexpr double kMinX = -0.5;
constexpr double kMaxX = 1.0;
constexpr double kWrap = kMaxX - kMinX;
// Added before wrapping, m (ten wraps): keeps fmod's argument positive for sliders going -x.
constexpr double kKeepPositive = 15.0;
// Speeds, m/s, either way along x.
constexpr double kMinSpeed = 0.08;
constexpr double kMaxSpeed = 0.2;
// Turn with x, rad/m: a slider shows its sides as it goes.
constexpr double kTurnPerMetre = 3.0;

}  // namespace

void plan_sliders(int count, const std::function<std::string()>& draw_type, core::Rng& rng,
                  ScenarioPlan& plan) {
  for (int i = 0; i < count; ++i) {
    PlacedObject o;
    o.type = draw_type();
    o.name = "scatter-" + o.type;
    const double y = kFirstRowY + kRowStep * i;
    const double x0 = rng.uniform(kMinX, kMaxX);
    const double speed = rng.uniform(kMinSpeed, kMaxSpeed) * (rng.uniform() < 0.5 ? -1.0 : 1.0);
    o.position = {x0, y};
    plan.scene.objects.push_back(o);
    plan.sliders.push_back({o.name, x0, y, speed});
  }
}

SliderMover::SliderMover(const World& world, const std::vector<ScenarioPlan::Slider>& sliders)
    : sliders_(sliders) {
  for (const auto& sl : sliders_) ids_.push_back(world.object(sl.name).id);
}

void SliderMover::move(World& world, double t) const {
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    const ScenarioPlan::Slider& sl = sliders_[i];
    const double x = std::fmod(sl.x0 + sl.speed * t - kMinX + kKeepPositive, kWrap) + kMinX;
    world.set_object_pose(ids_[i],
                          on_table(world.object(ids_[i]).type, x, sl.y, kTurnPerMetre * x));
  }
}

}  // namespace proprio::sim
