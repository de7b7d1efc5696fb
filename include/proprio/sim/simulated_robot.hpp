#pragma once
// The MuJoCo world behind robot::Robot: one persistent table scene of catalogue objects that the
// simulated arm pushes, push after push (objects stay where they were pushed). The learner sees
// only what robot::Robot gives (images, arm state, calibration, touch flag); the ground truth
// (object ids, names, poses, masks) is kept aside here for scoring.
//
// Frames: world = robot base frame (metres, z up, +x forward, table top z = 0).

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/robot/robot_interface.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_builder.hpp"

namespace proprio::sim {

/// The table a SimulatedRobot starts with.
struct TableOptions {
  /// Catalogue names of the objects; empty: `object_count` distinct objects drawn by `seed`.
  std::vector<std::string> objects;
  int object_count = 5;    ///< objects drawn when `objects` is empty (1..8)
  std::uint64_t seed = 1;  ///< draws the objects and scatters them
  int width = 640;         ///< image size, pixels
  int height = 480;
  bool shadows = false;  ///< shadow mapping (about half the frame rate in software GL)

  /// Throws Error naming the first bad option.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.object_count, {"objects", "Objects on the table, drawn from the catalogue by the seed",
                          core::between(1, 8)});
    v(self.seed, {"seed", "Seed of the table's objects and their places"});
    v(self.width, {"width", "Image width, px", core::between(64, 4096)});
    v(self.height, {"height", "Image height, px", core::between(48, 4096)});
    v(self.shadows, {"shadows", "Render shadows (slower)"});
  }
};

/// Ground truth of one object (never given to the learner).
struct ObjectTruth {
  ObjectId id = 0;                                     ///< its id in ground-truth masks
  std::string name;                                    ///< catalogue name
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< origin, world, m
  /// Centre of its bounding box in the world (the point a push through the middle aims at), m.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double yaw = 0;               ///< rad about world z
  double footprint_radius = 0;  ///< m
  bool on_table = true;         ///< still on the table top (not fallen off)
  bool upright = true;          ///< its z axis still points up (not toppled)
};

/// Where a scatter put one object.
struct Placement {
  std::string name;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< world x y of its origin, m
  double yaw = 0;                                      ///< rad
};

/// The part of the table objects are scattered over (m, world x y): in front of the arm, inside
/// the camera's view, clear of the arm's base.
struct ScatterRegion {
  Eigen::Vector2d min{0.08, -0.30};
  Eigen::Vector2d max{0.46, 0.30};
  /// Most distance from the base axis to an object's box centre, m: within the arm's reach
  /// (0.49 m at the table with the pitch free) with room to push from behind.
  double max_radius = 0.40;
  /// Least distance from the base axis to an object's box centre, plus its half diagonal, m.
  double base_clearance = 0.10;
  double gap = 0.03;  ///< least gap between two objects' footprints (yawed bounding boxes), m
};

/// Places `types` at random non-overlapping places (their bounding boxes, turned by their yaw,
/// `gap` apart) of `region` with random yaw (as a person
/// would put them down), from `seed`. Objects for which no room is found after many draws are put
/// where they overlap least. Deterministic in the seed.
std::vector<Placement> scatter_placements(const std::vector<const ObjectType*>& types,
                                          const ScatterRegion& region, std::uint64_t seed);

class SimulatedRobot final : public robot::Robot {
 public:
  /// Builds the table scene (catalogue objects scattered by the seed), the world and its renderer,
  /// parks the arm out of the view and lets the objects settle. Throws Error for bad options, an
  /// unknown object, or when no GL context can be had.
  SimulatedRobot(const TableOptions& options, const ObjectCatalogue& catalogue);
  ~SimulatedRobot() override;

  // --- robot::Robot ------------------------------------------------------------------------------
  robot::Look look() override;
  [[nodiscard]] geometry::Camera camera() const override;
  [[nodiscard]] const robot::Arm& arm() const override;
  [[nodiscard]] robot::JointVector joints() const override;
  /// The arm is put above the push's start at once (the transit is not simulated), lowered,
  /// pushes, is lifted, and the objects are left to come to rest; then the arm is parked out of
  /// the view again. The touch flag is MuJoCo's contact of the arm with any object. Throws Error,
  /// with nothing moved, when the arm put above the start would be inside an object (a tall one
  /// under the hand).
  robot::PushReport push(const robot::TablePush& push,
                         const robot::PushRecording& recording) override;

  // --- ground truth and the scene (not part of robot::Robot) ------------------------------------
  [[nodiscard]] std::vector<ObjectTruth> ground_truth() const;
  /// Object ids of the current view (CV_16UC1; 0 background, kArmId the arm).
  cv::Mat ground_truth_mask();
  /// Ids of the objects the arm touched during the last push (ascending).
  [[nodiscard]] const std::vector<ObjectId>& last_push_contacts() const;
  /// Puts every object at a random non-overlapping place (scatter_placements from `seed`) and
  /// lets them settle; logged. Returns the placements.
  std::vector<Placement> scatter(std::uint64_t seed);
  /// The table top's extent, world x y, m.
  [[nodiscard]] Eigen::Vector2d table_min() const;
  [[nodiscard]] Eigen::Vector2d table_max() const;

  // --- added for self-supervision's held-out views (loop/self_supervision_scoring) -------------
  /// Puts object i (in the order of ground_truth()) at places[i] (world x y of its origin, m,
  /// and yaw, rad; names are not checked), parks the arm and lets them settle. Throws Error
  /// unless there is one place per object.
  void place(const std::vector<Placement>& places);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace proprio::sim
