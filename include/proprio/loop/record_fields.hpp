#pragma once
// How the loop's records (push.json, push evaluation, selfsupervise.json and its decisions.jsonl,
// learn.json) write the values they share: table points, image boxes, measurements that may be
// absent (null), a putative object and the robot's execution of a push. Each is a derived value or
// a described struct (core/fields.hpp), so that a record's describe() names its keys once.

#include <Eigen/Core>
#include <opencv2/core/types.hpp>
#include <optional>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/planning/push_planner.hpp"
#include "proprio/robot/robot_interface.hpp"

namespace proprio::loop {

/// A table (m) or image (px) point as the JSON array [x, y].
inline std::vector<double> xy(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }

/// An image box as the JSON array [x, y, width, height], px.
inline std::vector<int> box_json(const cv::Rect& b) { return {b.x, b.y, b.width, b.height}; }

/// `x` when it was measured (>= 0), else null: the loop's distances and errors use -1 for "none".
inline core::Json measured_or_null(double x) { return x >= 0 ? core::Json(x) : core::Json(); }

/// An optional value, or null when it is empty (where the record keeps the key).
template <class T>
core::Json value_or_null(const std::optional<T>& x) {
  return x ? core::Json(*x) : core::Json();
}

/// A table point, or null when it was not measured.
inline core::Json xy_or_null(bool measured, const Eigen::Vector2d& p) {
  return measured ? core::Json(xy(p)) : core::Json();
}

/// A putative object as a record lists it: its table centre, feature count and image box, and
/// (with `with_pixel`) its centre in the image.
struct PutativeObjectRecord {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();        ///< p_c, table m
  Eigen::Vector2d centre_pixel = Eigen::Vector2d::Zero();  ///< mean feature position, px
  int features = 0;                                        ///< its feature points
  cv::Rect box;                                            ///< px
  bool with_pixel = true;  ///< whether the record lists centre_pixel

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(xy(self.centre), {"centre", "Centre p_c on the table, m"});
    if (self.with_pixel) v(xy(self.centre_pixel), {"centre_pixel", "Mean feature position, px"});
    v(self.features, {"features", "Feature points"});
    v(box_json(self.box), {"box", "Bounding box [x, y, width, height], px"});
  }
};

/// The putative objects of a view as records list them (largest first).
inline std::vector<PutativeObjectRecord> putative_object_records(const planning::PlanningView& view,
                                                                 bool with_pixel) {
  std::vector<PutativeObjectRecord> out;
  out.reserve(view.objects.size());
  for (const auto& o : view.objects) {
    out.push_back({o.centre, o.centre_pixel, static_cast<int>(o.pixels.size()), o.box, with_pixel});
  }
  return out;
}

/// What the robot did of a push (robot::PushReport), as push.json's "execution".
struct ExecutionRecord {
  const robot::PushReport* report = nullptr;  ///< not null

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    const robot::PushReport& r = *self.report;
    v(r.frames, {"frames", "Frames the camera took during the push"});
    v(r.touched, {"touched", "The touch signal was on in some frame"});
    v(value_or_null(r.first_touch_frame),
      {"first_touch_frame", "First frame with touch (null: none)"});
    v(r.seconds, {"seconds", "The robot's time the push took, s"});
    v(r.episode_dir, {"episode", "The episode written, or empty"});
  }
};

}  // namespace proprio::loop
