#pragma once
// The robot's own singulation check from what it measures (issue 19, 7.2 b): the objects'
// footprints from the registered depth image (robot::Look::depth, kept in
// planning::PlanningView::depth), not from the feature hulls. Every depth pixel is
// back-projected to the world; the points at least least_height above the table (inside the
// table region) are objects. Neighbouring points closer than `join` in 3D belong to one surface,
// so a gap of table between two objects or a jump in depth where one object stands in front of
// or on top of another separates them; each connected surface of at least least_pixels pixels is
// a footprint (table x y of its points). The chosen object is the footprint most of its blob's
// features lie on; it is alone when that is at least `clearance` from every other footprint, no
// other blob's features lie mostly on it, and no second footprint carries a quarter of its
// features (two objects seen as one blob). A depth jump also cuts one object into parts (a head
// above its body); with DepthAloneOptions::part_gap > 0 the chosen object is every footprint its
// blob owns (has the most features on) and every footprint no blob owns within part_gap of
// those, and it is merged only when those fall into two groups part_gap apart with a quarter of
// its features each. Tuning seed 1 (session 21): part_gap 0 was right more often (an object
// touching the chosen one without a blob of its own was taken for its part), so 0 is the default.
//
// Frames: world x y, m (robot base frame, table top z = 0); pixels as planning::PlanningView.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "proprio/geometry/camera.hpp"
#include "proprio/planning/push_planner.hpp"

namespace proprio::loop {

/// How depth pixels become footprints.
struct DepthFootprintOptions {
  /// Points lower than this above the table are the table, m (planning::kObjectLeastHeight).
  double least_height = planning::kObjectLeastHeight;
  /// Neighbouring points (4-neighbours) farther apart than this in 3D are on different surfaces,
  /// m: a depth discontinuity (one object in front of another) separates them.
  double join = 0.015;
  /// Surfaces of fewer pixels than this are noise (or a sliver at the image's edge), px.
  int least_pixels = 25;
  /// Throws Error when a value is not finite or out of range (least_height in [0, 0.1], join in
  /// (0, 0.2], least_pixels in [1, 100000]).
  void validate() const;
};

/// One object's footprint as the depth image shows it.
struct DepthFootprint {
  std::vector<Eigen::Vector2d> hull;  ///< convex hull of its points' table x y, m (CCW)
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< mean of its points' table x y, m
  double height = 0;                                 ///< its highest point above the table, m
  int pixels = 0;                                    ///< depth pixels on it
};

/// The footprints of one depth image.
struct DepthFootprints {
  cv::Mat1i labels;  ///< per pixel the footprint's index, -1 where none
  std::vector<DepthFootprint> parts;
};

/// The footprints of `depth` (CV_32FC1, metres along the optical axis; 0 or not finite: not
/// measured) seen by `camera` (its image size), points outside `region` (its edge band
/// included) or within its base_radius of the base axis left out. Empty `depth`: no footprints.
/// Throws Error on a depth image of another type or size, or bad options.
DepthFootprints depth_footprints(const cv::Mat& depth, const geometry::Camera& camera,
                                 const planning::TableRegion& region,
                                 const DepthFootprintOptions& options = {});

/// How depth_alone groups footprints.
struct DepthAloneOptions {
  /// Footprints no other blob owns within this of the chosen blob's are its parts, m (0: off,
  /// the default: every footprint but the one most of its features lie on is another object).
  double part_gap = 0.0;
  /// Throws Error when part_gap is not finite or outside [0, 0.1] m.
  void validate() const;
};

/// The robot's verdict on blob `chosen` of `view`.
struct DepthAlone {
  bool measured = false;  ///< false: no footprint under the chosen blob's features (no depth)
  bool alone = false;     ///< gap >= clearance and merged == false
  /// The least gap from the chosen footprint to any other footprint, m (0: another blob's
  /// features lie on it; infinity when it is the only one).
  double gap = 0;
  /// Two footprints (part_gap > 0: two groups of its parts part_gap apart) each carry at least a
  /// quarter of the chosen blob's features: the blob is two objects seen as one.
  bool merged = false;
  int footprint = -1;  ///< the chosen blob's footprint (the one most of its features lie on)
  /// Per blob of the view, the gap from the chosen footprint to the blob's own footprint, m (0:
  /// the same footprint; nullopt: the blob's features lie on no footprint, or it is the chosen).
  std::vector<std::optional<double>> blob_gaps;
  std::string why;  ///< one line for the decision log
};

/// The check for blob `chosen` of `view` with its footprints `fp` (depth_footprints of
/// view.depth). Throws Error when `chosen` is not a blob of `view`, `clearance` is not positive
/// or the labels are not of the view's image size, or bad options.
DepthAlone depth_alone(const DepthFootprints& fp, const planning::PlanningView& view, int chosen,
                       double clearance, const DepthAloneOptions& options = {});

}  // namespace proprio::loop
