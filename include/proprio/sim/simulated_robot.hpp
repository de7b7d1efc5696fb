#pragma once
// The MuJoCo world behind robot::Robot: one persistent table scene of catalogue objects that the
// simulated arm pushes, push after push (objects stay where they were pushed). The learner sees
// only what robot::Robot gives (images, arm state, calibration, touch flag); the ground truth
// (object ids, names, poses, masks) is kept aside here for scoring.
//
// Frames: world = robot base frame (metres, z up, +x forward, table top z = 0).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/robot/robot_interface.hpp"
#include "proprio/sim/backdrop.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_builder.hpp"

namespace proprio::sim {

/// The table a SimulatedRobot starts with: the objects to learn, clutter beside them, and what
/// stands behind the table (sim/backdrop.hpp, as the episode recorder offers it).
struct TableOptions {
  /// Catalogue names of the objects; empty: `object_count` distinct objects drawn by `seed`.
  std::vector<std::string> objects;
  int object_count = 5;    ///< objects drawn when `objects` is empty (1..8)
  std::uint64_t seed = 1;  ///< draws the objects, the clutter, the distractors, their places
  int width = 640;         ///< image size, pixels
  int height = 480;
  bool shadows = false;  ///< shadow mapping (about half the frame rate in software GL)
  /// Behind the table: nothing (plain), a photograph on a wall at the table's far edge (photo),
  /// or a video of people walking on it, advancing with the robot's clock, with `distractors`
  /// objects sliding to and fro in front of it (moving).
  Background background = Background::kPlain;
  std::filesystem::path background_photo = default_background_photo();  ///< photo
  std::filesystem::path background_video = default_background_video();  ///< moving
  /// Objects sliding about behind the work area (ground truth role "distractor"; they pass
  /// through the table's objects and the arm: PlacedObject::ghost); -1: 2 with the moving
  /// background, else 0.
  int distractors = -1;
  /// Other objects on the table (ground truth role "clutter"), scattered with the objects: a
  /// whole number N (N catalogue objects drawn by the seed from those not otherwise on the
  /// table) or comma-separated catalogue names; empty or "0": none. At most 8 objects and
  /// clutter together.
  std::string clutter;
  /// The arm's transit between pushes (from where it waits out of the view to above the push's
  /// start, and back) is simulated at this height of the pusher tip, m (above the tallest
  /// catalogue object, 0.19 m).
  double transit_height = 0.26;
  /// Record the transit to the push's start in the push's episode too (else only the lowering,
  /// push and lift are recorded; the transit's time counts on the robot's clock either way).
  bool record_transit = false;
  /// Write each push episode's ground-truth masks too (masks/, objects.json with the arm): for
  /// scoring oracles only (loop/self_supervision_scoring.hpp's oracle ladder); the learner never
  /// reads them. Not a command option: the oracle ladder's callers set it.
  bool record_masks = false;
  /// An RGB-D camera: look() fills robot::Look::depth from the renderer's depth pass (metres
  /// along the optical axis, the same pixels as the image; 0 where nothing is rendered). Off:
  /// Look::depth stays empty (a colour camera alone, as before).
  bool depth = false;
  /// Pushes turn the hand's roll so that the gripper's jaws lie across the push, beside the
  /// pusher (robot::PushMotionOptions::roll_across). Off: the roll stays at the park's (the jaws
  /// across the arm's radius).
  bool roll_across = false;

  /// Throws Error naming the first bad option (the clutter's names are checked against the
  /// catalogue when the robot is built).
  void validate() const;
  /// The number of distractors in effect (see `distractors`).
  [[nodiscard]] int distractor_count() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.object_count, {"objects", "Objects on the table, drawn from the catalogue by the seed",
                          core::between(1, 8)});
    v(self.seed, {"seed", "Seed of the table's objects and their places"});
    v(self.width, {"width", "Image width, px", core::between(64, 4096)});
    v(self.height, {"height", "Image height, px", core::between(48, 4096)});
    v(self.shadows, {"shadows", "Render shadows (slower)"});
    v.choice(self.background,
             {"background",
              "Behind the table: plain, photo (a photograph) or moving (video of people "
              "walking, with distractors)"},
             kBackgroundNames);
    v(self.background_photo, {"background_photo", "Photograph of the photo background"});
    v(self.background_video, {"background_video", "Video of the moving background"});
    v(self.distractors, {"distractors",
                         "Objects sliding about behind the work area; -1: 2 with the moving "
                         "background, else 0",
                         core::between(-1, 4)});
    v(self.clutter, {"clutter",
                     "Clutter on the table too: a number drawn by the seed, or catalogue names "
                     "(a,b,c)"});
    v(self.transit_height,
      {"transit_height", "Height of the pusher tip during the arm's transit between pushes, m",
       core::between(0.2, 0.35)});
    v(self.record_transit,
      {"record_transit", "Record the arm's transit to the push's start in the episode"});
    v(self.depth, {"depth",
                   "An RGB-D camera: each look has a depth image too (planning "
                   "measures objects' footprints and heights from it)"});
    v(self.roll_across, {"roll_across",
                         "Pushes turn the hand's roll so that the gripper's jaws lie across the "
                         "push, beside the pusher"});
  }
};

/// What an object is for on the robot's table (ObjectTruth::role).
enum class TableRole {
  kObject,      ///< one of TableOptions::objects (or drawn by object_count)
  kClutter,     ///< TableOptions::clutter
  kDistractor,  ///< slides about behind the work area (TableOptions::distractors)
};
inline constexpr core::ChoiceNames<TableRole, 3> kTableRoleNames{
    {{"object", TableRole::kObject},
     {"clutter", TableRole::kClutter},
     {"distractor", TableRole::kDistractor}}};

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
  TableRole role = TableRole::kObject;
};

/// When in a push the arm first touched an object (SimulatedRobot::last_push_contact_phases).
enum class ContactPhase {
  kTransit,  ///< on the way to above the push's start (before lowering)
  kPush,     ///< lowering, the push itself, lifting
  kReturn,   ///< on the way back to the park
};
inline constexpr core::ChoiceNames<ContactPhase, 3> kContactPhaseNames{
    {{"transit", ContactPhase::kTransit},
     {"push", ContactPhase::kPush},
     {"return", ContactPhase::kReturn}}};

/// An object the arm touched during a push, when it first did, and with which parts.
struct ArmContact {
  ObjectId id = 0;
  ContactPhase phase = ContactPhase::kPush;
  /// The arm's parts that touched it (arm_part_name), in the order of first touch.
  std::vector<std::string> parts;
};

/// The part of the simulated arm a geom belongs to (data/models/arm.xml): "pusher" (the pusher
/// finger), "jaws" (either gripper jaw), "palm", or "links" (any other arm geom).
[[nodiscard]] std::string arm_part_name(const std::string& geom_name);

/// Two objects (ids, a < b) in contact with each other during a push: ground truth for
/// diagnosis.
struct ObjectContact {
  ObjectId a = 0;
  ObjectId b = 0;
  ContactPhase phase = ContactPhase::kPush;  ///< when they first touched in the push
  bool already = false;                      ///< they were touching when the push began
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

/// An object's footprint on the table, as scatter_placements keeps objects apart: its bounding
/// box (ObjectType::half_extents, x y) about its centre, turned by its yaw about world z.
struct BoxFootprint {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< the box's centre, world x y, m
  Eigen::Vector2d half = Eigen::Vector2d::Zero();    ///< half extents along its own axes, m
  double yaw = 0;                                    ///< rad about world z
};

/// An object's footprint where the ground truth has it now (its centre's x y and its yaw),
/// with its type's box (`type` must be the object's catalogue type).
[[nodiscard]] BoxFootprint box_footprint(const ObjectTruth& truth, const ObjectType& type);

/// How far two footprints grown by `gap` / 2 each overlap, m: the least penetration over the
/// separating axes of both boxes; 0 when they are at least `gap` apart (gap in m, >= 0).
[[nodiscard]] double footprint_overlap(const BoxFootprint& a, const BoxFootprint& b, double gap);

/// Places `types` at random non-overlapping places (their bounding boxes, turned by their yaw,
/// `gap` apart) of `region` with random yaw (as a person would put them down), from `seed`:
/// the largest footprints first, each at the best of many random places; a draw in which an
/// object found no room is drawn again as a whole (the default region holds the default world's
/// 7 objects). Only when no draw of many gives every object room, the least-overlapping draw is
/// returned (logged). Deterministic in the seed; the result is in the order of `types`.
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
  /// The arm's transit (joint interpolation from where it waits, turned at a safe height, to
  /// `transit_height` above the start and down to the lift height above it: recorded when
  /// TableOptions::record_transit), then it is lowered, pushes, is lifted, and goes back the same
  /// way while the objects come to rest; every part takes time on the robot's clock. The touch
  /// flag is MuJoCo's contact of the arm with any object. Throws Error, with nothing moved, when
  /// the transit would meet an object (checked pose by pose before moving: a tall object under
  /// the hand above the start; an object resting against the arm's base or its first link, a
  /// cylinder turning on its axis, is in that contact at every pose and does not count) or the
  /// push is out of reach.
  robot::PushReport push(const robot::TablePush& push,
                         const robot::PushRecording& recording) override;
  /// The physics steps `seconds` (rounded to whole steps) with the arm's joint targets left where
  /// its last motion put them (the arm holds still); the distractors keep to their script and the
  /// moving backdrop's video goes on (the next look shows both at the new time); nothing is
  /// recorded. Throws Error for a time that is not finite, negative or over 10 s.
  void hold_still(double seconds) override;

  // --- ground truth and the scene (not part of robot::Robot) ------------------------------------
  [[nodiscard]] std::vector<ObjectTruth> ground_truth() const;
  /// Object ids of the current view (CV_16UC1; 0 background, kArmId the arm; distractors and
  /// clutter by their ids too).
  cv::Mat ground_truth_mask();
  /// Ids of the objects the arm touched during the last push (ascending).
  [[nodiscard]] const std::vector<ObjectId>& last_push_contacts() const;
  /// The same, each with the part of the push in which the arm first touched it (in the order
  /// of first touch).
  [[nodiscard]] const std::vector<ArmContact>& last_push_contact_phases() const;
  /// Pairs of objects (not the arm, the table or the distractors) in contact with each other at
  /// any time of the last push, in the order of first touch (ObjectContact::already: touching
  /// when it began): an object the pushed one (or the arm) drove into another.
  [[nodiscard]] const std::vector<ObjectContact>& last_push_object_contacts() const;
  /// Puts every object and the clutter (not the distractors) at a random non-overlapping place
  /// (scatter_placements from `seed`) and lets them settle; logged. Returns the placements.
  std::vector<Placement> scatter(std::uint64_t seed);
  /// The table top's extent, world x y, m.
  [[nodiscard]] Eigen::Vector2d table_min() const;
  [[nodiscard]] Eigen::Vector2d table_max() const;

  // --- added for self-supervision's held-out views (loop/self_supervision_scoring) -------------
  /// Puts object i (in the order of ground_truth(): objects, clutter, then distractors) at
  /// places[i] (world x y of its origin, m, and yaw, rad; names are not checked), parks the arm
  /// and lets them settle. Distractors keep to their script: places for them may be given (and
  /// are ignored) or left out. Throws Error unless there is one place per object and clutter.
  void place(const std::vector<Placement>& places);

  // --- the robot's clock -------------------------------------------------------------------------
  /// The robot waits `seconds` (the physics runs, the moving background and the distractors go
  /// on); nothing is recorded. Throws Error for a negative or non-finite time, or over an hour.
  void wait(double seconds);
  /// The robot's clock, s (the physics' time since the table was built).
  [[nodiscard]] double time() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace proprio::sim
