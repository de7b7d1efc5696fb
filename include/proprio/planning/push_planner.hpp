#pragma once
// Push planning (thesis 7.2.1; SPEC §5): putative objects from the live image as feature-density
// blobs (6.2), and a straight push through an object's centre of mass that leaves it over a
// target point, along the path of least feature density of the other objects (7.4-7.5).
//
// Works on images and the robot interface only (never the simulator): features are the dense
// grid points of textured patches, the camera calibration maps them to the table by
// back-projection (eqs 3.13-3.17), and the arm's inverse kinematics says what is reachable.
//
// Frames: table points are world x y (metres, robot base frame, table top z = 0); pixels are
// ideal image pixels (OpenCV: x right, y down).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/features/blobs.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/robot/robot_interface.hpp"

namespace proprio::planning {

/// The part of the table pushes may use: objects, paths and targets stay inside it (m).
struct TableRegion {
  Eigen::Vector2d min{-0.25, -0.50};
  Eigen::Vector2d max{0.85, 0.50};
  /// Features whose table point is within this of the region's edge are the edge, m.
  double edge_band = 0.03;
  /// Objects whose centre is nearer the arm's base axis than this are the arm's own body, m.
  double base_radius = 0.09;
};

/// What the goal of a push is.
enum class PushGoal {
  kTarget,  ///< a given table point
  kEdge,    ///< toward the edge of the view (clearing the table, thesis 7.2 step b)
};
inline constexpr core::ChoiceNames<PushGoal, 2> kPushGoalNames{
    {{"target", PushGoal::kTarget}, {"edge", PushGoal::kEdge}}};

/// How an object's centre p_c and footprint come from its features.
enum class CentreMethod {
  /// The mean feature position back-projected at centre_height (the thesis's centre of mass).
  /// Tall objects come out too far from the camera: their features lie above the table.
  kFeatures,
  /// Parallax corrected from the footprint: the blob's edge nearest the camera is the object's
  /// foot (on the table); its lateral width (across the line of sight, where parallax does not
  /// stretch it) is taken as its depth too, and p_c is the middle of that footprint.
  kFootprint,
  /// Parallax corrected from the base contour: features back-projected onto the table top
  /// (z = 0) lie, for every point of a vertical edge, on one ray from the camera's foot, so their
  /// bearings around it span the footprint's whatever their height; the nearest feature at the
  /// two outermost bearings (the silhouette's outermost vertical edges' feet) are the
  /// footprint's tangent points, and p_c is their midpoint moved away from the camera by r^2 / D
  /// (exact for a circle of radius r at distance D). The footprint (the hull) is the nearest
  /// feature per bearing and its reflection through p_c. Right for tall boxes and cylinders
  /// (a 15 cm box within 7 mm, where kFeatures is 30 mm off), but the depth along the line of
  /// sight is a guess for other shapes: on tables 1-30 the centre was 18.7 mm off (median)
  /// against 10.9 mm for kFeatures (a spirit level 96 mm, a box 35 mm; the bottle 37 -> 11 mm),
  /// without the r^2 / D term 34.9 mm; not the default (docs/results/push.md).
  kBase,
};
inline constexpr core::ChoiceNames<CentreMethod, 3> kCentreMethodNames{
    {{"features", CentreMethod::kFeatures},
     {"footprint", CentreMethod::kFootprint},
     {"base", CentreMethod::kBase}}};

struct PushPlanOptions {
  // Putative objects (6.2).
  int grid_step = 6;         ///< spacing of the dense feature grid, px
  int patch = 12;            ///< side of the patch whose contrast is measured, px
  double min_contrast = 10;  ///< grey-level standard deviation a patch needs to be a feature
  /// Blobs: sigma 6 px, threshold 4 (about two thirds of the density of a fully textured patch with
  /// a 6 px grid), so that objects a few centimetres apart stay apart.
  features::BlobOptions blobs{6.0, 4.0, 8};
  /// Height above the table at which feature points are back-projected, m: the middle of a
  /// typical object's textured side (corrects part of the parallax of tall objects). 3.5 cm: on
  /// tables 1-100 the closed loop's median final distance was 19.9 mm against 23.4 mm at 2 cm and
  /// 24.7 mm at 5 cm (docs/results/push.md).
  double centre_height = 0.035;
  /// kFeatures: on tables 1-30 the closed loop's median final distance was 25 mm against 37 mm
  /// for kBase and the centre 10.9 mm off against 18.7 mm (docs/results/push.md).
  CentreMethod centre = CentreMethod::kFeatures;
  // Sampling (7.2.1): random approach lengths and targets, the least-cost path kept.
  int candidates = 48;          ///< paths sampled
  double min_approach = 0.02;   ///< pusher start to the object's edge, least, m
  double max_approach = 0.06;   ///< and most, m
  double target_spread = 0.01;  ///< kTarget: targets sampled within this of the given one, m
  double min_distance = 0.06;   ///< kEdge: least distance the object is pushed, m
  double max_distance = 0.16;   ///< kEdge: most, m
  double path_step = 0.005;     ///< spacing of the cost integral's samples along a path, m
  double table_margin = 0.03;   ///< paths and pushed objects keep this far inside the region, m
  double tip_height = 0.008;    ///< pusher tip above the table while pushing, m
  double push_speed = 0.05;     ///< m/s
  /// kTarget: a target nearer than this to the object's centre is reached (PlanOutcome::kAtTarget)
  /// and sampled targets nearer than this are not pushed to, m. A closed loop whose tolerance is
  /// below it stops at it.
  double least_push = 0.01;
  /// Objects whose height was measured (depth, PutativeObject::height): the pusher's tip at this
  /// fraction of the pushed object's height where that is above tip_height, at most
  /// kMostTipHeight, for objects no taller than tip_raise_height (push_tip_height). 0 (the
  /// default): tip_height for every object.
  double tip_fraction = 0;
  /// m: objects measured taller than this keep tip_height (a bottle pushed higher toppled).
  double tip_raise_height = 0.15;
  /// The pusher's radius, m: its side, not its axis, meets the object, so the push ends this much
  /// short of where the axis would put the object's back edge (push_through_centre). 0 (the
  /// default): the axis (the object goes on by the pusher's radius); the simulated arm's pusher
  /// is a capsule of 8 mm radius.
  double pusher_radius = 0;
  /// Objects measured at least this tall (m) are pushed at tall_push_speed (push_speed_for).
  double tall_height = 0.06;
  /// m/s; 0 (the default): push_speed for every object.
  double tall_push_speed = 0;
  /// Least gap kept between the corridor the pushed object sweeps (its hull carried from p_c to
  /// p_t) and every other putative object's hull, m; a path that keeps less is blocked by the
  /// shortfall (path_clearance), which outweighs the feature-density cost. 0 (the default: 1 cm
  /// with hand_clearance 3 cm and waypoints gave no better figures on tables 1-100,
  /// docs/results/push.md): not checked.
  double clearance = 0;
  /// Least gap kept between the pusher's own path (p_s to its end) and every other hull, m: the
  /// hand's half width (its fingers reach 3 cm to either side of the pusher, 3-10 cm above its
  /// tip; 0.03 was tried). 0 (the default, see clearance): not checked.
  double hand_clearance = 0;
  /// kTarget: paths sampled besides the direct ones that go round a blocked line through a
  /// waypoint (the push moves the object to the waypoint; the next push, re-planned, goes on to
  /// the target); taken only when they are clearer by more than a few millimetres. 0 (the
  /// default: a single push must end at its target): none; loop::push_once uses it for every
  /// push of its closed loop but the last (loop::kViaPoints: 0, 24 was tried).
  int via_points = 0;
  /// Least gap between the arm coming down to the pusher's start (its hand and low forearm) and
  /// every other putative object's hull, m; paths that keep less, or whose forearm passes over
  /// the pushed object itself, are not sampled (descent_blocked: the robot would refuse them).
  /// 0 (the default): not checked. selfsupervise: 0.04 (the fingers reach 3 cm either side).
  double descent_clearance = 0;
  /// Least gap kept between the arm's own poses on its way down to the pusher's start and what
  /// the depth image sees above the table, m (descent_meets_object against descent_map: the
  /// transit's vertical leg from kDescentTops down to the start, posed by inverse kinematics every
  /// kDescentStep, each moving part of the arm against the highest point seen in each 5 mm cell,
  /// the pushed object's too; without depth, the putative objects' hulls raised to their measured
  /// heights, an unmeasured one counted as tall). A path whose descent meets something is not
  /// taken; the next best is (PushPlan::rejected_descent). 0 (the default): not checked.
  double descent_pose_margin = 0;
  /// With descent_pose_margin: when the descent of every path that could be taken meets
  /// something, the best of them is taken anyway (as without the check; PushPlan::descent_met)
  /// instead of no plan. false (the default): no plan (PlanOutcome::kUnreachable).
  bool descent_pose_fallback = false;
  /// The robot turns the jaws across the push (sim::TableOptions::roll_across), so
  /// descent_pose_margin poses the hand that way. Not a command-line option: loop::push_once sets
  /// it from the simulated table's options.
  bool roll_across = false;
  /// Objects measured (depth) lower than the pusher's tip plus this, m, are pushed with the
  /// gripper's jaws along the push (robot::JawLine::kAlong: the one ahead passes over the object,
  /// and the hand is 3 cm wide across the push instead of 6 cm); others, and objects of unknown
  /// height, as the robot holds them (kRobot). 0 (the default): every push kRobot. The jaws hang
  /// kFingerDrop (3 cm) above the tip: 0.025 leaves 5 mm (push_jaws).
  double jaws_along_height = 0;
  /// Least gap kept between the region the pushed object sweeps and every other putative object's
  /// hull, m (sweep_lack: its hull, and at the end that hull turned kSweepTurn either way about
  /// its centre for the turn a push gives round and long objects, carried from p_c to p_t); a
  /// path that keeps less is blocked by the shortfall, like clearance. A blocked push toward a
  /// given target is also tried shortened (kTarget): the object stopped on the same line, 5 mm
  /// steps back, where its swept region is first clear, at kShortCost per metre left to go (the
  /// next push of the loop, re-planned, cannot go on through the neighbour either). 0 (the
  /// default): not checked, no shortened pushes.
  double sweep_margin = 0;
  /// With sweep_margin: a neighbour the pushed object touches already counts too (the margin, as
  /// running into one) when the push goes toward it (sweep_lack's `touching`). false (the
  /// default): a touching neighbour counts nothing.
  bool sweep_touching = false;
  /// With sweep_margin: the turn allowance by the pushed object's shape (sweep_turn: a box-like
  /// footprint, pushed through its centre, hardly turns) instead of kSweepTurn for every object.
  /// false (the default): kSweepTurn.
  bool sweep_turn_by_shape = false;
  /// Depth: a blob whose depth points hold two or more tops that meet at a step in height of at
  /// least this, m (depth_tops), is split into them (split_by_depth), so that two touching
  /// objects of different heights are two putative objects. 0 (the default): not split.
  double depth_split = 0;
  /// Depth: least gap kept between the hand above the pusher (hand_lack: the jaws, from
  /// kFingerDrop above the tip, the palm from kPalmDrop, and the low forearm, swept along the
  /// push) and every other putative object whose measured height reaches that part, m; a path
  /// that keeps less is blocked by the shortfall, like sweep_margin, and a blocked push toward a
  /// given target is also tried shortened where the hand is first clear. 0 (the default): not
  /// checked.
  double hand_margin = 0;
  /// With hand_margin: a push whose hand is blocked with the jaws across the push is also tried
  /// with the jaws along it (3 cm wide across instead of 6 cm) when the pushed object is low
  /// enough for the jaw ahead to pass over it; the less blocked is kept. false (the default): the
  /// jaws as push_jaws says.
  bool hand_jaws = false;
  /// With hand_margin: a push whose hand is blocked is also tried with the pusher's tip raised
  /// in 5 mm steps by up to this, m (the tip at most kMostTipHeight and kRaiseFraction of the
  /// pushed object's measured height), so that the hand passes over a lower neighbour; the least
  /// blocked, then lowest, kept. 0 (the default): the tip as push_tip_height says.
  double hand_raise = 0;
  /// With hand_margin: a push whose sweep-shortened end (sweep_margin) is not clear for the
  /// hand at any point of its line keeps the first point clear of the sweep, its hand's
  /// shortfall counted as blocking (session 22's check then made the full, blocked push
  /// instead). false (the default): session 22's behaviour.
  bool hand_keep_short = false;
  /// kTarget: when no direct push (nor its shortened form) reaches the target clear, this many
  /// waypoints in a fixed fan round the line (turned 20-100 degrees off it either way, 4-10 cm
  /// from p_c) are also tried; each is scored with both legs' shortfalls (clearance,
  /// sweep_margin, hand_margin) and taken when its score beats the best direct push's (a
  /// waypoint costs as much as 3 mm of blocking or 3 cm of shortening: it spends a push). 0 (the
  /// default): none (via_points samples waypoints at random for every push instead).
  /// loop::push_once sets it to 0 on its last push.
  int via_blocked = 0;
  /// kTarget: when the pushed object's footprint put at the target (its hull carried from p_c)
  /// comes within this of another putative object's hull (the target lies against a neighbour, so
  /// reaching it means pushing that neighbour too), the goal becomes the nearest point to the
  /// target (rings kFreeTargetStep apart, kFreeTargetAngles points each, out to kFreeTargetMost)
  /// inside the table region whose straight push keeps this margin (sweep_lack with no turn
  /// allowance: the swept region from p_c and the footprint there), the point nearest the object
  /// on the first ring that has one (PushPlan::target_moved). No such point: the target as
  /// given. m; 0 (the default): the target as given.
  double free_target_margin = 0;
  /// The closed loop's correction pushes (loop::push_once, the second push and after; the planner
  /// itself does not read it): each is planned with hand_margin at least this, and one whose hand
  /// is still blocked (PushPlan::hand_blocked > 0: the jaws, palm or low forearm would come nearer
  /// than this to another putative object that reaches them, hand_lack) is not made; the loop
  /// ends with the object where the last push left it. The first push is planned as before.
  /// m; 0 (the default): corrections are planned and made as the first push.
  double correction_hand_margin = 0;
  /// The closed loop's first push (loop::push_once; the planner itself does not read it): planned
  /// by plan_push_hand_clear with this margin, so that a first push whose hand (the jaws, palm or
  /// low forearm, hand_lack) would come nearer than this to another putative object is replaced by
  /// one whose hand is clear: the jaws along the push over a low object (hand_jaws) or a push to a
  /// waypoint round the line (via_blocked, kFirstHandVia waypoints; the loop's next push goes on
  /// to the target), the least blocked kept; when none is clear the first push is made as without
  /// it. m; 0 (the planner's default): the first push is planned as the options say; the
  /// closed loop's default is loop::kLoopFirstHandMargin (session 30).
  double first_hand_margin = 0;
  /// The closed loop's retries after the robot refused a push (loop::push_once; the planner
  /// itself does not read it): each retry is planned with descent_pose_margin at least this and
  /// descent_pose_fallback on, so that the path taken is the least-cost one whose arm, posed by
  /// its own kinematics on the way down to the start (every moving link, the upper arm too),
  /// keeps this far from what the depth image sees, the pushed object included; when every path's
  /// way down meets something, the retry is planned as without it. The refusal says only that the
  /// arm would meet something (the robot's names are not read). m; 0 (the default): the retries
  /// only start farther behind the object (PushOptions::retries). Session 31 (docs/results/
  /// push.md): +1 only-intended table of 200 on the tuning seeds, none on the held-out 10001-10100
  /// (the refused tables there have no path whose way down is clear), so the loop keeps it off.
  double refusal_pose_margin = 0;
  /// Depth: a pushed object measured tall enough to reach the hand's palm (tall_start: height >=
  /// the tip + kPalmDrop - kDescentHeightMargin; the bottle, the giraffe, the rabbit) is pushed
  /// only on a path whose arm, posed by its own kinematics (tall_push_meets: the palm and the
  /// links, not the pusher nor the jaws), keeps this far from what the depth image sees, the
  /// pushed object included, on its way down to the start, and does not touch the object with
  /// them kTallLead before the pusher meets it; each path is also tried from farther behind
  /// (kTallMostApproach), ranked after the others, so a path that keeps clear is planned as
  /// without the option. No such path: no plan (kUnreachable; PushPlan::rejected_tall), never a
  /// fallback: a tall object the hand comes down on or leans into topples and rolls (session 31:
  /// a bottle off the table on 10008, 10040, 10074). m; 0 (the planner's default): not checked;
  /// the closed loop's default is loop::kLoopTallStartClearance (session 32).
  double tall_start_clearance = 0;
  /// Depth: a push whose first contact with the pushed object (push_contact from its depth
  /// points) gives a tipping ratio above this (kToppleFriction * contact height / its foot's
  /// reach ahead of the centre) is not sampled (PushPlan::rejected_topple): the object would
  /// fall over rather than slide (session 29: the giraffe and the bike toppled in 30 of 34
  /// pushes, their bodies met above their legs and wheels). When every path is rejected so the
  /// plan fails (kUnreachable), and a caller that tries other sides (selfsupervise's learn
  /// pushes) tries them. 0 (the default), or no depth image: not checked.
  double topple_ratio = 0;
  /// With topple_ratio: a push that would tip the object is also tried with the jaws turned
  /// across the push (robot::JawLine::kAcross: the fingers 2-3 cm to either side, not ahead), then
  /// with its line shifted sideways in 1 cm steps by up to this, m, either way (the pusher aimed
  /// at a low part, a leg or a wheel, off the centre: the object turns as well as slides; a
  /// departure from thesis 7.2.1's push through the centre, PushPlan::offset); the first that
  /// does not tip it is kept. 0 (the default): neither.
  double topple_offset = 0;
  std::uint64_t seed = 1;

  /// Throws Error naming the first option out of its bounds or inconsistent.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.grid_step, {"grid_step", "Dense feature grid spacing, px", core::between(1, 64)});
    v(self.min_contrast,
      {"min_contrast", "Grey-level standard deviation of a feature's patch, 0-255",
       core::between(0, 255)});
    v(self.blobs.sigma,
      {"blob_sigma", "Feature density kernel sigma, px (eq 6.3)", core::positive_at_most(200)});
    v(self.blobs.threshold,
      {"blob_threshold", "Density threshold of a blob (features within sigma)", core::positive()});
    v(self.centre_height,
      {"centre_height", "Height features are back-projected at, m", core::between(0, 0.2)});
    v.choice(self.centre,
             {"centre",
              "Object centre: features (mean, thesis), footprint or base (parallax corrected)"},
             kCentreMethodNames);
    v(self.candidates,
      {"candidates", "Paths sampled; the least-cost one is kept", core::between(1, 10000)});
    v(self.min_approach,
      {"min_approach", "Least approach before the object, m", core::between(0.005, 0.3)});
    v(self.max_approach,
      {"max_approach", "Most approach before the object, m", core::between(0.005, 0.3)});
    v(self.target_spread,
      {"target_spread", "Targets sampled within this of the given one, m", core::between(0, 0.1)});
    v(self.min_distance,
      {"min_distance", "Edge goal: least push distance, m", core::between(0.01, 0.5)});
    v(self.max_distance,
      {"max_distance", "Edge goal: most push distance, m", core::between(0.01, 0.5)});
    v(self.path_step, {"path_step", "Cost integral sample spacing, m", core::between(0.001, 0.05)});
    v(self.table_margin,
      {"table_margin", "Margin inside the table region, m", core::between(0, 0.2)});
    v(self.tip_height,
      {"tip_height", "Pusher tip height above the table, m", core::between(0.002, 0.05)});
    v(self.push_speed, {"push_speed", "Push speed, m/s", core::positive_at_most(0.5)});
    v(self.least_push, {"least_push", "Target goal: an object this near its target is there, m",
                        core::between(0.002, 0.05)});
    v(self.tip_fraction,
      {"tip_fraction",
       "Depth: the pusher's tip at this fraction of the object's measured height (0: tip_height)",
       core::between(0, 0.5)});
    v(self.tip_raise_height,
      {"tip_raise_height", "Depth: objects taller than this keep tip_height, m",
       core::between(0.005, 0.5)});
    v(self.pusher_radius,
      {"pusher_radius", "The pusher's radius: pushes end this much short, m (0: the axis)",
       core::between(0, 0.05)});
    v(self.tall_height,
      {"tall_height", "Depth: objects measured this tall are pushed at tall_push_speed, m",
       core::between(0.005, 0.5)});
    v(self.tall_push_speed,
      {"tall_push_speed", "Depth: push speed of tall objects, m/s (0: push_speed)",
       core::between(0, 0.5)});
    v(self.clearance,
      {"clearance", "Least gap between the pushed object's corridor and other objects, m",
       core::between(0, 0.1)});
    v(self.hand_clearance,
      {"hand_clearance", "Least gap between the pusher's path and other objects, m",
       core::between(0, 0.1)});
    v(self.via_points,
      {"via_points", "Target goal: paths sampled through a waypoint round a blocked line",
       core::between(0, 1000)});
    v(self.descent_clearance,
      {"descent_clearance", "Least gap between the arm's way down and other objects, m (0: off)",
       core::between(0, 0.2)});
    v(self.descent_pose_margin,
      {"descent_pose_margin",
       "Depth: least gap between the arm's poses on its way down to the start and the objects' "
       "measured footprints x heights, m (0: off)",
       core::between(0, 0.05)});
    v(self.descent_pose_fallback,
      {"descent_pose_fallback",
       "With descent_pose_margin: when every path's way down meets an object, the best is pushed "
       "anyway instead of none"});
    v(self.jaws_along_height,
      {"jaws_along_height",
       "Depth: objects lower than the tip plus this are pushed with the jaws along the push, m "
       "(0: never)",
       core::between(0, 0.1)});
    v(self.sweep_margin,
      {"sweep_margin",
       "Least gap between the pushed object's swept region and other objects, m; blocked pushes "
       "to a target are also tried shortened (0: off)",
       core::between(0, 0.05)});
    v(self.sweep_touching,
      {"sweep_touching",
       "With sweep_margin: a neighbour touching the pushed object counts when the push goes "
       "toward it"});
    v(self.sweep_turn_by_shape,
      {"sweep_turn_by_shape",
       "With sweep_margin: the swept region's turn allowance by the object's shape (boxes hardly "
       "turn)"});
    v(self.depth_split,
      {"depth_split",
       "Depth: blobs holding tops that meet at a height step of at least this are split, m (0: "
       "off)",
       core::between(0, 0.1)});
    v(self.hand_margin,
      {"hand_margin",
       "Depth: least gap between the hand above the pusher and other objects as tall as it, m; "
       "blocked pushes to a target are also tried shortened (0: off)",
       core::between(0, 0.05)});
    v(self.hand_jaws,
      {"hand_jaws",
       "With hand_margin: a blocked push is also tried with the jaws along it (low objects)"});
    v(self.hand_raise,
      {"hand_raise",
       "With hand_margin: a blocked push is also tried with the tip raised by up to this, m (0: "
       "off)",
       core::between(0, 0.03)});
    v(self.hand_keep_short,
      {"hand_keep_short",
       "With hand_margin: a sweep-shortened push whose line is nowhere clear for the hand keeps "
       "its shortened end"});
    v(self.via_blocked,
      {"via_blocked",
       "Target goal: waypoints in a fixed fan tried when no direct push reaches the target "
       "clear (0: off)",
       core::between(0, 200)});
    v(self.free_target_margin,
      {"free_target_margin",
       "Target goal: a target whose object footprint would lie within this of another object is "
       "moved to the nearest point a straight push reaches clear, m (0: off)",
       core::between(0, 0.05)});
    v(self.correction_hand_margin,
      {"correction_hand_margin",
       "Closed loop: correction pushes are planned with at least this hand margin and not made "
       "when the hand is still blocked, m (0: off)",
       core::between(0, 0.05)});
    v(self.first_hand_margin,
      {"first_hand_margin",
       "Closed loop: a first push whose hand would come nearer than this to another object is "
       "replaced by one with the jaws along or through a waypoint whose hand is clear, m (0: off)",
       core::between(0, 0.05)});
    v(self.refusal_pose_margin,
      {"refusal_pose_margin",
       "Closed loop: a push the robot refused is re-planned with the arm's poses on its way down "
       "checked against the depth image (descent_pose_margin with fallback) at this margin, m "
       "(0: off)",
       core::between(0, 0.05)});
    v(self.tall_start_clearance,
      {"tall_start_clearance",
       "Depth: a pushed object tall enough to reach the palm is pushed only from a start whose "
       "arm keeps this far from the depth image on its way down (approaches up to 15 cm), else "
       "not at all, m (0: off)",
       core::between(0, 0.05)});
    v(self.topple_ratio,
      {"topple_ratio",
       "Depth: pushes whose first contact, judged from the object's depth points, would tip it "
       "(friction x contact height / foot reach above this) are not taken (0: off)",
       core::between(0, 10)});
    v(self.topple_offset,
      {"topple_offset",
       "With topple_ratio: a tipping push is tried with the jaws across, then shifted sideways by "
       "up to this to meet a low part, m (0: neither)",
       core::between(0, 0.05)});
    v(self.seed, {"plan_seed", "Seed of the sampled paths"});
  }
};

/// One putative object: a feature-density blob (6.2) mapped to the table.
struct PutativeObject {
  cv::Rect box;                         ///< blob bounding box, px
  cv::Mat1b mask;                       ///< box-sized, 255 inside the blob
  std::vector<Eigen::Vector2d> pixels;  ///< its feature points, px
  Eigen::Vector2d centre_pixel;         ///< mean feature position, px
  Eigen::Vector2d centre;               ///< p_c on the table, m (PushPlanOptions::centre says how)
  std::vector<Eigen::Vector2d> hull_pixels;  ///< convex hull of the features, px
  std::vector<Eigen::Vector2d> hull;         ///< its footprint on the table, m (CCW; see centre)
  /// The features' hull back-projected at PushPlanOptions::centre_height, m (CCW): where the
  /// image of the object lies on the table (the hull itself with CentreMethod::kFeatures), what
  /// find_pushed_object carries to find the object's features again.
  std::vector<Eigen::Vector2d> extent;
  /// Measured from depth (make_planning_view with a depth image, measure_footprint): the height
  /// of the object's top above the table, m; `centre` and `hull` are then its measured footprint
  /// (the table-plane hull of its 3D points and that hull's centroid) instead of the back-
  /// projection at centre_height. Empty without depth (or too few depth points on the object):
  /// the planner knows no height and treats the object as tall.
  std::optional<double> height;
};

/// An object's footprint and height measured from depth points (measure_footprint).
struct MeasuredFootprint {
  std::vector<Eigen::Vector2d> hull;  ///< convex hull of the points' table x y, m (CCW)
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< the hull's area centroid, m
  double height = 0;  ///< the top's height above the table (98th percentile of z), m
  int points = 0;     ///< depth points on the object (above kObjectLeastHeight)
};

/// Depth points lower than this above the table are the table, not an object, m.
inline constexpr double kObjectLeastHeight = 0.005;
/// Fewer depth points than this on a blob: no footprint measured (the blob keeps the
/// back-projected one).
inline constexpr int kFootprintLeastPoints = 20;

/// The 3D footprint of what `depth` (CV_32FC1 metres along the optical axis, as robot::Look::depth;
/// 0 or not finite: no measurement) sees inside the convex polygon `hull_pixels` (ideal pixels)
/// and the 8-bit `mask` (placed at `box` in the image; empty: the polygon alone): each pixel
/// (every `step` px) back-projected to the world, X = R^T (depth K^-1 (u, v, 1) - t) (base frame,
/// table top z = 0); points at least kObjectLeastHeight above the table are the object. Their
/// table x y's convex hull is its footprint for convex objects whose top or sides the camera sees
/// (a box's top covers its footprint; a cylinder's unseen back half is missing, so its centre
/// comes out up to 4r / 3pi nearer the camera). Empty (nullopt) when fewer than
/// kFootprintLeastPoints points are on an object.
std::optional<MeasuredFootprint> measure_footprint(const cv::Mat& depth,
                                                   const geometry::Camera& camera,
                                                   const std::vector<Eigen::Vector2d>& hull_pixels,
                                                   const cv::Mat& mask = {}, cv::Rect box = {},
                                                   int step = 1);

/// The depth points measure_footprint takes as the object's (same arguments, same checks): each
/// pixel inside `hull_pixels` and `mask`, every `step` px, back-projected to the world (base frame,
/// table top z = 0, m), those at least kObjectLeastHeight above the table. Empty when none (or
/// fewer than 3 hull pixels).
std::vector<Eigen::Vector3d> object_depth_points(const cv::Mat& depth,
                                                 const geometry::Camera& camera,
                                                 const std::vector<Eigen::Vector2d>& hull_pixels,
                                                 const cv::Mat& mask = {}, cv::Rect box = {},
                                                 int step = 1);

/// Friction push_contact assumes between an object and the table: the simulated table's 0.8
/// (MuJoCo takes the larger of two geoms' coefficients, so every object slides at >= 0.8).
inline constexpr double kToppleFriction = 0.8;
/// push_contact: the object's points met within this of the first contact (along the push) are
/// met at once, m (the object gives a little as the first point is pushed).
inline constexpr double kContactBand = 0.004;
/// push_contact: the object's foot, what it stands on, is its points up to this high, m.
inline constexpr double kFootHeight = 0.02;
/// The pusher's radius (data/models/arm.xml's capsule, its tip the end effector), m.
inline constexpr double kPusherRadius = 0.008;
/// How far the jaws reach along their own line (arm.xml: the finger boxes 3 cm wide), and how
/// long they are (7 cm, from kFingerDrop above the tip up), m.
inline constexpr double kJawLength = 0.07;

/// What a push meets first (push_contact), judged from the object's depth points.
struct PushContact {
  bool met = false;   ///< the pusher or the hand meets one of the points
  bool jaws = false;  ///< the first contact is the jaws' or the palm's, not the pusher rod's
  /// The lowest point met at the first contact (within kContactBand of it), m above the table.
  double height = 0;
  /// How far the object's foot (points up to kFootHeight, or all when none are that low) reaches
  /// ahead of its centre along the push, m (at least 1 mm): the edge it would tip about.
  double base = 0;
  /// kToppleFriction * height / base: an object pushed at `height` slides while its friction
  /// (kToppleFriction times its weight) turns it about its foot's front edge less than its weight
  /// at `base` holds it back; above 1 it tips over instead (statics of a rigid body, its centre
  /// of mass over `centre`). 0 when nothing is met.
  double ratio = 0;
};

/// Where a straight push through `centre` along `direction` (table m, unit) first meets an object
/// whose depth points (object_depth_points, table frame, m) are `points`: the hand's parts swept
/// along the line, the vertical pusher rod (radius kPusherRadius, from `tip_height` up to the
/// palm), the jaws from kFingerDrop above the tip (`jaws`, `roll_across` as push_jaws and
/// sim::TableOptions::roll_across set them: across the push, the finger boxes kFingerReach - 1 cm
/// to kFingerReach off the line and kJawHalf ahead of the axis; along, one of them kFingerReach
/// ahead, kJawHalf either side; the robot's own roll unknown, a disc of radius kFingerReach). The
/// palm (kPalmDrop above the tip) is left out: judged as a disc of kPalmReach it met every object
/// taller than 11 cm first, the 23.5 cm bottle too, yet with the jaws across the bottle pushed at
/// its foot stood in 4 of 5 single pushes (session 29). The camera sees one side of the object: the
/// points are taken with their reflection through `centre` (the unseen side as the seen one
/// turned half round). The first contact's lowest point is where the object is pushed once it
/// starts to turn (its higher points lean away from a vertical rod), so a rod that meets a leg
/// or a wheel near the table pushes it there, and one that passes between them under a body
/// meets the body high. Thesis 7.2.1's push through the centre is kept; only whether it tips is
/// judged. `offset` (m) shifts the pusher's line sideways, to the left of `direction` (its foot
/// stays judged about `centre`). Throws Error when `direction` is not a unit vector or tip_height
/// is negative.
PushContact push_contact(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector2d& centre,
                         const Eigen::Vector2d& direction, double tip_height,
                         robot::JawLine jaws = robot::JawLine::kRobot, bool roll_across = false,
                         double offset = 0);

/// Side of the cells of depth_tops's top-down height map, m.
inline constexpr double kTopCell = 0.004;
/// A top of depth_tops keeps at least this area once a cell is taken off its rim, m^2 (a steep
/// rim cut off its object by the step, a thin strip, a few stray points are no top).
inline constexpr double kTopLeastArea = 6e-4;

/// The tops of what a depth image sees inside a blob (depth_tops).
struct DepthTops {
  /// Box-sized: 0 outside the blob's mask, else 1..count, the top nearest the pixel (in the
  /// image) among the sampled depth points that lie on a top.
  cv::Mat1i labels;
  int count = 0;  ///< tops found (0: too few depth points above the table)
};

/// The separate tops of what `depth` (CV_32FC1 metres along the optical axis, as
/// robot::Look::depth) sees inside a blob (the 8-bit `mask` placed at `box` in the image): its
/// depth points, every `step` px, at least kObjectLeastHeight above the table, go into a top-down
/// map of the highest point in each kTopCell cell (an object's vertical sides fall under its top's
/// rim); cells within two cells of each other whose heights differ by less than `jump` (m) are one
/// top. Two
/// touching objects whose tops differ in height by `jump` or more so come apart along the step
/// between them; two of equal height do not, and one object whose own surface has such a step is
/// cut there. Tops smaller than kTopLeastArea once closed and eroded by a cell are left out (their
/// pixels go to the nearest top). Throws Error on a bad depth image, mask, step (< 1) or jump (<=
/// 0).
DepthTops depth_tops(const cv::Mat& depth, const geometry::Camera& camera, const cv::Mat& mask,
                     cv::Rect box, double jump, int step = 2);

/// What the planner knows of the view: the features, their density (eq 6.3) and the putative
/// objects, sorted by size (largest first).
struct PlanningView {
  geometry::Camera camera;
  cv::Size image_size;
  std::vector<cv::KeyPoint> features;
  cv::Mat1f density;  ///< (h * N)(x) of eq 6.3 over all features
  std::vector<PutativeObject> objects;
  /// The look's depth image (robot::Look::depth: CV_32FC1, metres along the optical axis) or
  /// empty; with it every putative object's footprint and height are measured.
  cv::Mat depth;
};

/// Feature points of an 8-bit image: the dense grid points (spacing options.grid_step) whose
/// patch has a grey-level standard deviation of at least options.min_contrast (as the dense
/// features of 7.3.3 keep them; only locations, no descriptors). Points within a patch of a
/// non-zero pixel of `ignore` (CV_8U, e.g. Look::arm_mask; empty: none) are left out.
std::vector<cv::KeyPoint> textured_points(const cv::Mat& image, const PushPlanOptions& options,
                                          const cv::Mat& ignore = {});

/// The planning view of `features` seen by `camera`: density, blobs, each blob's centre and
/// convex hull back-projected to the table at options.centre_height. Features whose
/// back-projection onto the table top falls outside `region` (table edges, the world beyond) are
/// left out first; blobs whose centre falls within region.base_radius of the base axis are
/// dropped. With `depth` (robot::Look::depth; empty: none, everything as without it) each blob's
/// centre, hull and height are measured from the depth points inside its features' hull
/// (measure_footprint) where it has enough of them. Throws Error when `depth` is not CV_32FC1 of
/// the camera's image size.
PlanningView make_planning_view(const std::vector<cv::KeyPoint>& features,
                                const geometry::Camera& camera, const TableRegion& region,
                                const PushPlanOptions& options, const cv::Mat& depth = {});
/// make_planning_view of textured_points(look.image, ignoring look.arm_mask), with look.depth
/// (its arm pixels cleared).
PlanningView look_for_objects(const robot::Look& look, const TableRegion& region,
                              const PushPlanOptions& options);

/// Share of an object's feature points whose neighbourhood changed between two looks, 0-1: the
/// grey-level difference of `before` and `after` (8-bit, same size), averaged over a 9 x 9 px
/// window, of at least kMotionChange at the point (the motion of a push, thesis Ch 4's putative
/// object "after a push" in its simplest form).
double moved_share(const cv::Mat& before, const cv::Mat& after, const PutativeObject& object);
/// Grey levels of mean change that count as motion in moved_share.
inline constexpr double kMotionChange = 6.0;

/// The object just pushed, found from the images only (the putative object "after a push" of the
/// issue, a motion segmentation in its simplest form): the features of `after_view` whose
/// neighbourhood changed between `before_image` and `after_image` (kMotionChange) and whose table
/// point lies within a quarter of `radius` of the `previous` object's hull carried to `expected`
/// (where the push should have left its centre, table m) are grouped into density blobs of their
/// own (options.blobs), so that an object that now touches a neighbour, still or swept along, is
/// not merged with it; the moving blob whose centre is nearest `expected` within `radius` is
/// taken: the whole putative object holding it when that is the object alone (85% of its
/// features inside the carried hull, or 85% of them moved and it is at most 1.5 times the
/// object's feature count before), else the moving blob itself, appended to after_view.objects.
/// When nothing moved there (the push missed it), the putative object nearest the previous centre
/// within a quarter of `radius` is taken. Returns its index, or -1 when none.
int find_pushed_object(const cv::Mat& before_image, const cv::Mat& after_image,
                       PlanningView& after_view, const PutativeObject& previous,
                       const Eigen::Vector2d& expected, double radius, const TableRegion& region,
                       const PushPlanOptions& options);

/// Splits the putative objects of `view` by the image regions of objects the robot knows
/// (thesis 8.1.1: what moved with the arm in a push is one object; the rest of a blob that held
/// it is another putative object). `regions`: 8-bit masks of the view's image size, non-zero
/// where known object r lies (e.g. its push's motion segmentation carried to this look), or
/// empty (unknown). Each feature point of a blob goes to the first region holding it, else to
/// the rest. A blob is split when at least two parts would hold `min_features` points each: the
/// part of each such region (the blob's mask within the region) and each connected part of the
/// rest (the blob's mask outside every region); points of smaller parts stay with the largest
/// part. The first part keeps the blob's place in view.objects, the others are appended; each
/// part's centre and hull are made as make_planning_view makes a blob's. Returns, per region,
/// the index of the putative object holding most of its points (at least min_features), -1 when
/// none does.
std::vector<int> split_putative_objects(PlanningView& view, const std::vector<cv::Mat>& regions,
                                        int min_features, const TableRegion& region,
                                        const PushPlanOptions& options);

/// Splits every putative object of `view` whose blob holds two or more depth tops
/// (depth_tops of view.depth with options.depth_split as the jump) into them
/// (split_putative_objects with each top's part of the blob as a region, options.blobs
/// min_features points per part): touching objects merged into one blob become separate putative
/// objects with their own measured footprints. make_planning_view calls it when
/// options.depth_split > 0. Returns the number of putative objects added; 0 without depth or
/// with depth_split 0.
int split_by_depth(PlanningView& view, const TableRegion& region, const PushPlanOptions& options);

/// How planning ended.
enum class PlanOutcome {
  kPlanned,         ///< a path was found
  kNoObjects,       ///< no putative object in view
  kUnknownObject,   ///< the object index is not one of the view's
  kTargetOffTable,  ///< the target (and the object over it) is outside the table region
  kUnreachable,     ///< no sampled path is reachable by the arm (IK) inside the region
  kAtTarget,        ///< the object's centre is already within 1 cm of the target
};
inline constexpr core::ChoiceNames<PlanOutcome, 6> kPlanOutcomeNames{
    {{"planned", PlanOutcome::kPlanned},
     {"at-target", PlanOutcome::kAtTarget},
     {"no-objects", PlanOutcome::kNoObjects},
     {"unknown-object", PlanOutcome::kUnknownObject},
     {"target-off-table", PlanOutcome::kTargetOffTable},
     {"unreachable", PlanOutcome::kUnreachable}}};

struct PushPlan {
  PlanOutcome outcome = PlanOutcome::kNoObjects;
  std::string message;
  int object = -1;                                   ///< index into PlanningView::objects
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< p_c, table m
  Eigen::Vector2d target = Eigen::Vector2d::Zero();  ///< p_t chosen, table m
  /// The push: start p_s behind the object on the line through p_c and p_t, end where the
  /// object's centre is over p_t (valid when outcome is kPlanned).
  robot::TablePush push;
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  ///< n = (p_t - p_s) / |p_t - p_s|
  double edge_distance = 0;  ///< d: p_c to the hull's edge behind it, along -n, m (Algorithm 4)
  double approach = 0;       ///< pusher start to that edge, m
  double cost = 0;           ///< feature density of the other objects along the path (eq 7.5)
  /// How much the path (both legs through a waypoint) lacks of the clearances, summed over the
  /// other objects, m (path_clearance); 0: clear.
  double blocked = 0;
  /// Of blocked, the hand's part (hand_lack against PushPlanOptions::hand_margin, with the jaws'
  /// line and tip height the plan takes), m; 0: the hand is clear or hand_margin is 0.
  double hand_blocked = 0;
  /// kTarget: how much nearer to the object than the target asked the plan's target is, m (a
  /// push shortened where the object's swept region meets another object, sweep_margin); 0 for
  /// a push that goes all the way (within target_spread).
  double shortened = 0;
  /// kTarget: the push goes to a waypoint round a blocked line (target is that waypoint), not to
  /// the given target; the next push, re-planned, goes on.
  bool via = false;
  int sampled = 0;          ///< candidate paths sampled
  int rejected_region = 0;  ///< of them outside the table region
  int rejected_reach = 0;   ///< of them out of the arm's reach
  /// Of them whose arm would meet an object on its way down (PushPlanOptions::descent_pose_margin).
  int rejected_descent = 0;
  /// Of them that would tip the object over (PushPlanOptions::topple_ratio).
  int rejected_topple = 0;
  /// Of them whose arm would meet something on its way down to a tall pushed object's start
  /// (PushPlanOptions::tall_start_clearance).
  int rejected_tall = 0;
  /// The taken push's tipping ratio (push_contact), when PushPlanOptions::topple_ratio is on and
  /// depth measured the object; 0 otherwise.
  double topple = 0;
  /// topple_offset: the push's line is shifted this far to the left of its direction, m (0:
  /// through the centre).
  double offset = 0;
  /// The plan's own descent meets an object: every path's did, and
  /// PushPlanOptions::descent_pose_fallback took the best of them anyway.
  bool descent_met = false;
  /// kTarget with PushPlanOptions::free_target_margin: how far the goal was moved from the target
  /// asked (that target lay against another object), m; 0: not moved.
  double target_moved = 0;
  /// plan_push_hand_clear: the plan is its clear-hand try (hand_margin, hand_jaws, via_blocked),
  /// not the push the options alone give.
  bool hand_cleared = false;
  /// plan_push_hand_clear: its clear-hand try was not clear (or not planned), so the plan is the
  /// one the options alone give; how far the try fell short (its PushPlan::blocked plus its
  /// PushPlan::shortened), m, or -1 when the try planned nothing. 0: not tried, or kept.
  double hand_fallback = 0;
  double seconds = 0;  ///< wall-clock planning time
};

/// Distance from `p` (inside the convex polygon `hull`, CCW) to its boundary along direction
/// `u` (unit): the exact line-hull intersection (Algorithm 4's walk, done in closed form). 0 when
/// p is outside or on the boundary.
double distance_to_hull_edge(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p,
                             const Eigen::Vector2d& u);

/// The start and end of a push of an object with centre p_c to target p_t (SPEC §5, the sign of
/// the thesis's n corrected): n = (p_t - p_c) / |p_t - p_c|, p_s = p_c - (d + approach) n, where
/// d is the distance from p_c to the hull's edge along -n, and the pusher stops at p_t - d n so
/// that p_c ends over p_t; the path is f(t) = p_s + t n (eq 7.4). A pusher of radius
/// `pusher_radius` (m) meets the object with its side, so it stops at p_t - (d + pusher_radius) n.
/// Throws Error when p_t = p_c.
robot::TablePush push_through_centre(const std::vector<Eigen::Vector2d>& hull,
                                     const Eigen::Vector2d& centre, const Eigen::Vector2d& target,
                                     double approach, double height, double speed,
                                     double pusher_radius = 0);

/// Cost of a push (eq 7.5): the density of `density` (the other objects' features; the pushed
/// object's hull zeroed) integrated, in steps of `step` m, along the pusher's path and the
/// corridor the pushed object sweeps (its `hull` carried from p_c to p_t: five lines across its
/// width, from its back edge at the start to its front edge at the end), table points projected
/// into the image at `height`. Units: features x m.
double path_cost(const cv::Mat1f& density, const geometry::Camera& camera,
                 const robot::TablePush& push, const std::vector<Eigen::Vector2d>& hull,
                 const Eigen::Vector2d& centre, const Eigen::Vector2d& target, double height,
                 double step);

/// The highest tip PushPlanOptions::tip_fraction puts the pusher at, m (the fingers are
/// kFingerDrop above the tip, the palm kPalmDrop).
inline constexpr double kMostTipHeight = 0.05;

/// The pusher tip's height above the table for pushing `object`, m: options.tip_height, or with a
/// measured height h (depth) and options.tip_fraction > 0, tip_fraction * h where that is higher,
/// at most kMostTipHeight, when h <= options.tip_raise_height. A tall object pushed at its foot is
/// pushed by the fingers too (kFingerDrop above the tip), and turns or topples about its foot.
double push_tip_height(const PutativeObject& object, const PushPlanOptions& options);

/// How the jaws lie when pushing `object` with the tip at `tip_height` (m): JawLine::kAlong when
/// options.jaws_along_height > 0 and the object's measured height (depth) is below tip_height +
/// jaws_along_height, else kRobot (the robot's own setting).
robot::JawLine push_jaws(const PutativeObject& object, double tip_height,
                         const PushPlanOptions& options);

/// The push speed for `object`, m/s: options.tall_push_speed when that is set (> 0) and the
/// object's measured height (depth) is at least options.tall_height, else options.push_speed.
double push_speed_for(const PutativeObject& object, const PushPlanOptions& options);

/// Distance between two convex polygons (either orientation; 1 or 2 points are a point or a
/// segment), any units; 0 when they overlap.
double polygon_distance(const std::vector<Eigen::Vector2d>& a,
                        const std::vector<Eigen::Vector2d>& b);

/// How much a push lacks of the clearances (m, summed over `others`, the other objects' hulls):
/// the corridor the pushed object sweeps (`hull`, around `centre`, carried to `target`) comes
/// nearer than `clearance` to an other hull (nearer than it was before the push, when it was
/// nearer already; running into one counts at least `clearance`), or the pusher's path
/// (push.start to push.end) keeps less than `hand_clearance` from one. 0: clear.
double path_clearance(const robot::TablePush& push, const std::vector<Eigen::Vector2d>& hull,
                      const Eigen::Vector2d& centre, const Eigen::Vector2d& target,
                      const std::vector<std::vector<Eigen::Vector2d>>& others, double clearance,
                      double hand_clearance);

/// Either way the pushed object may turn in a push, rad (sweep_region).
inline constexpr double kSweepTurn = 0.26;  // 15 degrees
/// Score of a shortened push per metre it leaves to go (features x m per m): as much as 10 mm of
/// blocking per 10 cm.
inline constexpr double kShortCost = 100.0;

/// sweep_turn: the turn allowance of a box-like footprint, rad (3 degrees).
inline constexpr double kBoxTurn = 0.05;
/// sweep_turn: a footprint is box-like when its hull fills at least this share of its least-area
/// enclosing rectangle (a disc fills pi / 4 = 0.785 of its square)...
inline constexpr double kBoxFill = 0.9;
/// ...and that rectangle is at most this many times as long as it is wide (long objects turn).
inline constexpr double kBoxAspect = 2.5;

/// The turn a push may give an object of footprint `hull` (convex, table m), rad: kBoxTurn for a
/// box-like one (kBoxFill, kBoxAspect), else kSweepTurn (round and long objects; fewer than 3
/// points too).
double sweep_turn(const std::vector<Eigen::Vector2d>& hull);

/// The region (convex, CCW) the pushed object sweeps from `centre` to `target`: its `hull` at the
/// start and, at the target, that hull carried there and turned by 0 and +-`turn` (rad) about its
/// centre, and all between. Table m.
std::vector<Eigen::Vector2d> sweep_region(const std::vector<Eigen::Vector2d>& hull,
                                          const Eigen::Vector2d& centre,
                                          const Eigen::Vector2d& target, double turn = kSweepTurn);

/// How much the pushed object's swept region (sweep_region, turned `turn` either way) lacks of
/// `margin` against `others` (the other objects' hulls), summed, m: coming nearer than `margin` to
/// an other hull (nearer than it was before the push, when it was nearer already) counts the
/// shortfall; running into one counts at least `margin`; a hull it touched already before the push
/// counts nothing (it cannot be kept clear of), unless `touching` and the push goes toward it (the
/// object's hull drawn back kTouchBack against the push no longer touches it): then it counts
/// `margin`. 0: clear, or margin <= 0.
double sweep_lack(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& centre,
                  const Eigen::Vector2d& target,
                  const std::vector<std::vector<Eigen::Vector2d>>& others, double margin,
                  bool touching = false, double turn = kSweepTurn);
/// sweep_lack: how far a touching neighbour's push is drawn back to tell whether it goes toward
/// it, m.
inline constexpr double kTouchBack = 0.01;
/// free_target_margin: the search's rings round the target are this far apart, m...
inline constexpr double kFreeTargetStep = 0.005;
/// ...each of this many points...
inline constexpr int kFreeTargetAngles = 24;
/// ...out to this distance from the target, m.
inline constexpr double kFreeTargetMost = 0.10;

/// How far from the pusher's start toward the arm's base (the table origin) the forearm hangs
/// low at the end of the transit's way down, m (descent_blocked).
inline constexpr double kForearmReach = 0.15;

/// Whether the arm coming down to `start` (table m, robot base frame: the base at the origin)
/// would meet a putative object: the hand and the low forearm (the segment from `start`
/// kForearmReach toward the base) pass within `clearance` of an other object's hull (`others`),
/// or over the pushed object's own `hull`. The planner knows no heights: every blob counts as
/// tall. Session 15 (seed 1 of selfsupervise): every refused transit was the palm, fingers or
/// forearm (arm_link3) meeting the bottle or the giraffe at 85-98% of the transit, the way down.
bool descent_blocked(const Eigen::Vector2d& start, const std::vector<Eigen::Vector2d>& hull,
                     const std::vector<std::vector<Eigen::Vector2d>>& others, double clearance);

/// The hand above the pusher's tip when it points down (data/models/arm.xml): the fingers' lowest
/// points kFingerDrop above the tip, reaching kFingerReach from its axis; the palm's lowest
/// kPalmDrop above it, reaching kPalmReach; the forearm higher still. m.
inline constexpr double kFingerDrop = 0.03;
inline constexpr double kFingerReach = 0.03;
inline constexpr double kPalmDrop = 0.10;
inline constexpr double kPalmReach = 0.045;
/// An object whose top is within this below a part of the hand still counts as meeting it, m.
inline constexpr double kDescentHeightMargin = 0.005;
/// Added to the hand's reach for the hand's orientation (its pitch is free where the arm reaches
/// far), m.
inline constexpr double kDescentReachMargin = 0.01;

/// The jaws' half extent across their own line (the finger boxes are 3 cm wide), and the palm's,
/// m (data/models/arm.xml).
inline constexpr double kJawHalf = 0.015;
inline constexpr double kPalmHalf = 0.025;
/// hand_raise: the tip is raised to at most this fraction of the pushed object's measured height.
inline constexpr double kRaiseFraction = 0.5;

/// The footprint (convex, CCW, table m) the pusher's tip sweeps from `start` to `end` carrying a
/// box `along` m either side of its axis along the push and `across` m either side across it (a
/// rectangle from start - along n to end + along n, 2 across wide). Throws Error when start =
/// end or a half extent is negative.
std::vector<Eigen::Vector2d> hand_footprint(const Eigen::Vector2d& start,
                                            const Eigen::Vector2d& end, double along,
                                            double across);

/// How much the hand above the pusher lacks of `margin` against `others` along `push` (its tip at
/// push.height), m, summed over the objects: with the jaws across the push (`jaws_along` false)
/// the jaws sweep hand_footprint(kJawHalf along, kFingerReach across), along it (kFingerReach
/// along, kJawHalf across); the palm (kPalmHalf and kPalmReach, the same way round); the low
/// forearm the quadrilateral from the push's start and end kForearmReach toward the base (the
/// origin). An object counts against the jaws when its measured height reaches them (h >=
/// push.height + kFingerDrop - kDescentHeightMargin), against the palm and forearm when it
/// reaches the palm (kPalmDrop); an object of unknown height counts as tall. A part that comes
/// nearer than `margin` to an object counts the shortfall, and when it runs into it at least
/// `margin` plus how far the pusher's line lies inside the part's reach of the object (so a
/// deeper overlap counts more). 0: clear, or margin <= 0. The pushed object is not in `others`.
double hand_lack(const robot::TablePush& push, bool jaws_along,
                 const std::vector<const PutativeObject*>& others, double margin);

/// descent_blocked with the objects' heights where they were measured (PutativeObject::height,
/// from depth); an object without one is treated as descent_blocked treats every object (tall).
/// With a height h above the table, the pusher's tip at `tip_height` (m):
/// - an object lower than the fingers (h < tip_height + kFingerDrop - kDescentHeightMargin) never
///   blocks: the hand passes above it;
/// - the pushed object (`pushed`) blocks when the start is nearer its hull than the part of the
///   hand that reaches its height (plus kDescentReachMargin): kFingerReach, or kPalmReach once it
///   reaches the palm (h >=
///   tip_height + kPalmDrop - kDescentHeightMargin), when also the forearm must not pass over it;
///   its height so sets how far behind it the hand may come down;
/// - another object blocks when it is within `clearance` (at least the reach of the part of the
///   hand it reaches, plus kDescentReachMargin) of the hand (the start), or, once it reaches the
///   palm, within `clearance` of the low forearm (the segment from the start kForearmReach toward
///   the base).
/// Units: m, table frame (the base at the origin).
bool descent_blocked(const Eigen::Vector2d& start, const PutativeObject& pushed,
                     const std::vector<const PutativeObject*>& others, double clearance,
                     double tip_height);

/// The heights above the pusher's start from which the robot's transit comes straight down
/// (sim::TableOptions::transit_height's default, and the lower ones it falls back to where that
/// is out of reach), m.
inline constexpr std::array<double, 3> kDescentTops{0.26, 0.22, 0.18};
/// PushPlanOptions::tall_start_clearance: each direct path sampled for a tall pushed object is
/// also tried from farther behind, its approach lengthened by this less max_approach (2-6 cm
/// become 11-15 cm), ranked after every other path, m.
inline constexpr double kTallMostApproach = 0.15;

/// Whether PushPlanOptions::tall_start_clearance checks the pushes of `object` with its pusher's
/// tip at `tip_height` (m): the option on and the object's measured height (depth) reaching the
/// palm (height >= tip_height + kPalmDrop - kDescentHeightMargin). An object of unknown height is
/// not checked (nothing tells that it is tall).
bool tall_start(const PutativeObject& object, double tip_height, const PushPlanOptions& options);

/// Spacing of the poses descent_meets_object checks on the way down, m.
inline constexpr double kDescentStep = 0.01;
/// descent_map: an object of unknown height (no depth) counts as this tall, m.
inline constexpr double kUnknownHeight = 1.0;

/// Side of the cells of a DescentMap, m.
inline constexpr double kDescentCell = 0.005;

/// What the arm may meet on its way down to a push, as the robot sees it (not the simulator's
/// truth): a top-down map of the highest point above the table in each kDescentCell cell of the
/// table region.
struct DescentMap {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< table m: the corner of cell (0, 0)
  /// Rows along y, columns along x: the highest point seen in the cell, m above the table (0:
  /// nothing kObjectLeastHeight or more above it).
  cv::Mat1f top;
};

/// The DescentMap of `view` over `region`: with depth (view.depth, robot::Look::depth with the
/// arm's pixels cleared), every second pixel's depth point at least kObjectLeastHeight above the
/// table, in the cell under it; without depth, each putative object's hull (table x y) filled to
/// its measured height (PutativeObject::height), kUnknownHeight where none was measured.
DescentMap descent_map(const PlanningView& view, const TableRegion& region);

/// Whether the arm, coming down to `push`'s start as the simulated robot does (from the first of
/// kDescentTops it reaches above the start, straight down to the start at push.height; the roll
/// j5 as robot::plan_push_motion sets it from `q_rest`, across the push when `roll_across` or
/// push.jaws say so), meets what `map` holds: at poses every kDescentStep (inverse kinematics,
/// each seeded by the one above), every moving part of the arm (its colliding geoms below the
/// first link: capsules and cylinders as balls along their axes, boxes as their surface points,
/// other shapes as their bounding spheres) comes within `margin` of a cell's column (its centre
/// within the ball's radius, `margin` and half the cell's diagonal; its top above the ball's
/// lowest point less `margin`). The pushed object is in the map too: a hand that comes down on
/// it meets it. Returns the first part that meets one (its geom's name, its height and the
/// cell's top), or nullopt. Units: m, table frame (the base at the origin). Throws Error when no
/// pose of the way down can be reached or the margin is negative.
std::optional<std::string> descent_meets_object(robot::ArmState& arm, const robot::TablePush& push,
                                                const robot::JointVector& q_rest,
                                                const DescentMap& map, double margin,
                                                bool roll_across);

/// tall_push_meets: the hand is posed this far before the pusher meets the pushed object, m (a
/// palm or link that meets the object there leans into it: the object is pushed high first).
inline constexpr double kTallLead = 0.03;

/// Whether the arm's parts above the jaws (the palm and the links; not the pusher nor a finger,
/// which meet a pushed object low, push_contact) meet what `map` holds when pushing a tall object
/// (PushPlanOptions::tall_start_clearance): on the way down to `push`'s start as
/// descent_meets_object poses it, at `margin`; or touching it (margin 0) with the pusher's tip on
/// the line kTallLead before `contact` m from the start (contact: where the pusher's side first
/// meets the object, the approach less the pusher's radius). Returns the part that meets
/// something (its name, height and the cell's top) or nullopt. Throws Error when a pose cannot be
/// reached or the margin or `contact` is negative. Units: m, table frame.
std::optional<std::string> tall_push_meets(robot::ArmState& arm, const robot::TablePush& push,
                                           const robot::JointVector& q_rest, const DescentMap& map,
                                           double margin, bool roll_across, double contact);

/// The density of every putative object but view.objects[object]: its blob and its convex hull
/// zeroed (eq 7.5's "own hull zeroed").
cv::Mat1f density_of_others(const PlanningView& view, int object);

/// Plans a push of view.objects[object] toward `target` (kTarget, table m) or toward the edge of
/// the view (kEdge; `target` ignored): samples options.candidates targets and approaches (and,
/// for kTarget, options.via_points pushes to a waypoint beside the line), rejects
/// those that leave the region or that the arm cannot reach from `q_rest` (robot::reachable at the
/// start, above it and at the end), and keeps the one of least blocking (path_clearance against
/// the other putative objects' hulls, those holding p_c left out), then least cost, whose whole
/// motion
/// (robot::plan_push_motion: lowering, push, lifting) tracks without a joint jump. Bad outside
/// input (a non-finite target, bad options) throws Error; every planning failure is an outcome with
/// a message.
PushPlan plan_push(const PlanningView& view, int object, PushGoal goal,
                   const Eigen::Vector2d& target, const TableRegion& region, robot::ArmState& arm,
                   const robot::JointVector& q_rest, const PushPlanOptions& options);

/// Waypoints plan_push_hand_clear tries round a first push whose hand is blocked (via_blocked's
/// fan: session 23's 24).
inline constexpr int kFirstHandVia = 24;

/// The options a retry is planned with after the robot refused a push (its arm would meet
/// something on the way to the start): `options` with descent_pose_margin at least
/// refusal_pose_margin and descent_pose_fallback on, so that plan_push takes the least-cost path
/// whose arm, posed on its way down by the arm's own kinematics (every moving link), keeps that
/// far from the depth image's heights (the pushed object's too), or the best path as before when
/// none does. `options` unchanged when refusal_pose_margin is 0 (the default). (Session 31 also
/// tried adding 24 random waypoints to the retry: on the tuning tables it executed more refused
/// tables but left objects far from their targets; not kept.)
[[nodiscard]] PushPlanOptions after_refusal(const PushPlanOptions& options);

/// A push whose hand keeps clear of the other putative objects (PushPlanOptions::first_hand_margin,
/// the closed loop's first push): plan_push with hand_margin at least `margin` (m), hand_jaws on
/// and, when `via` > 0, via_blocked at least `via` (the push may go to a waypoint round the
/// line; pass 0 when no push follows to go on to the target). That plan is returned
/// (PushPlan::hand_cleared) when it is wholly clear (PushPlan::blocked 0: with a waypoint, both
/// legs) and goes all the way (not shortened: the loop ends after a shortened push); otherwise
/// plan_push with `options` as given (PushPlan::hand_fallback says how blocked the try was).
/// `margin` 0: plan_push alone. Throws Error as plan_push does, and for a margin outside
/// [0, 0.05] or a negative `via`.
PushPlan plan_push_hand_clear(const PlanningView& view, int object, PushGoal goal,
                              const Eigen::Vector2d& target, const TableRegion& region,
                              robot::ArmState& arm, const robot::JointVector& q_rest,
                              const PushPlanOptions& options, double margin, int via);

}  // namespace proprio::planning
