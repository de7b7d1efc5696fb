#pragma once
// The robot as the learning and planning code see it (thesis 7.2: look, plan, push): a camera
// that looks at a table and an arm that pushes along it. The simulated world implements it
// (sim::SimulatedRobot); a driver of a real arm and camera implements the same two calls.
//
// What a real arm and camera must provide to sit behind this interface:
// - a calibrated camera fixed relative to the arm's base: K, distortion, R, t with P = K [R | t]
//   mapping the robot base frame (metres, z up, table top z = 0) to pixels (geometry::Camera,
//   calib.yml; `proprio calib` makes it from DLT, thesis 3.2);
// - a grab of the current image (8-bit BGR) with a time stamp, and the arm's joint angles and
//   end-effector position at that time; optionally where its own body is in the image (its
//   link geometry drawn through the calibration), so that the arm is not taken for an object;
// - optionally a depth image registered to the colour image (an RGB-D camera: the same pixels,
//   the same calibration), in metres along the optical axis; planning then measures each
//   object's footprint and height instead of assuming one height for all;
// - a joint-position controller that follows a joint trajectory sampled at a fixed rate (the
//   samples come from plan_push_motion: inverse kinematics of a straight line at the pusher's
//   height, eqs 3.4-3.6), and a way to move the pusher above the table to the push's start
//   without touching the objects (a transit at a safe height);
// - while it pushes: images at a steady frame rate, each with the arm's state, and a touch
//   signal (a contact sensor, a force threshold at the wrist, or a current spike), which becomes
//   the episode's `touching` column (the first-touch frame of eq 4.18);
// - the episode written with episode::EpisodeWriter (docs/formats/episode.md), without ground
//   truth: no masks and no object list.
//
// Frames: world = robot base frame (metres, z up, table top z = 0); image pixels follow OpenCV
// (x right, y down, centres at integer coordinates).

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "proprio/core/fields.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/geometry/backprojection.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/joint_tracking.hpp"

namespace proprio::robot {

/// What the robot sees and feels now.
struct Look {
  cv::Mat image;                                 ///< 8-bit BGR, the camera's current view
  double t = 0;                                  ///< time of the image, s (the robot's clock)
  JointVector q = JointVector::Zero();           ///< joint angles, rad
  Eigen::Vector3d ee = Eigen::Vector3d::Zero();  ///< end-effector (pusher tip), world, m
  geometry::Camera camera;                       ///< the calibration, image size included
  /// CV_8U, 255 where the arm's own body is in view (the robot's self-model: its links drawn
  /// through the calibration at the joint angles q); empty when the robot cannot tell.
  cv::Mat arm_mask;
  /// CV_32FC1, the image's size: each pixel's depth, metres along the camera's optical axis (the
  /// camera frame's z, not the length of the ray), registered to `image` through `camera` (the
  /// point seen at ideal pixel (u, v) is X_cam = depth * K^-1 (u, v, 1)^T, world X = R^T (X_cam -
  /// t)); 0 where nothing was measured. Empty when the robot has no depth camera: every user then
  /// behaves as with a colour camera alone.
  cv::Mat depth;
};

/// How the gripper's jaws lie during a push. The simulated hand carries them 2.5 cm either side
/// of the pusher along the last link's y axis, 3 to 10 cm above its tip: across the push they are
/// beside the pusher (the hand 6 cm wide across the push, nothing ahead of the pusher but the jaws'
/// 1.5 cm half width); along it one is ahead of the pusher, one behind (the hand 3 cm wide across
/// the push; the one ahead passes over an object lower than 3 cm above the tip).
enum class JawLine {
  kRobot,   ///< the robot's own setting (PushMotionOptions::roll_across)
  kAcross,  ///< across the push at its middle (fingers_across_roll)
  kAlong,   ///< along the push at its middle (fingers_along_roll)
};
inline constexpr core::ChoiceNames<JawLine, 3> kJawLineNames{
    {{"robot", JawLine::kRobot}, {"across", JawLine::kAcross}, {"along", JawLine::kAlong}}};

/// A straight push along the table, in the table plane (world x y, m).
struct TablePush {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  ///< where the pusher tip goes down, m
  Eigen::Vector2d end = Eigen::Vector2d::Zero();    ///< where it stops, m
  /// Height of the pusher tip above the table while it pushes, m. 8 mm: below half the height
  /// of the thinnest catalogue objects (CD 1 cm, calculator 2 cm) and clear of the table.
  double height = 0.008;
  double speed = 0.05;             ///< mean speed along the line, m/s
  JawLine jaws = JawLine::kRobot;  ///< how the gripper's jaws lie (the roll j5)

  /// Throws Error when a value is not finite, the line is shorter than 5 mm, the height is
  /// outside (0, 0.1] m or the speed outside (0, 0.5] m/s.
  void validate() const;
  [[nodiscard]] double length() const { return (end - start).norm(); }
};

/// The same push given in image pixels (ideal, undistorted), turned into a TablePush by
/// back-projection onto the table plane.
struct ImagePush {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  ///< pixels
  Eigen::Vector2d end = Eigen::Vector2d::Zero();    ///< pixels
  double height = 0.008;                            ///< m, as TablePush::height
  double speed = 0.05;                              ///< m/s
};

/// The table point seen at ideal pixel `pixel`: the back-projection of eqs 3.13-3.17 onto the
/// plane z = `plane_height` (m; 0 = the table top). Throws Error when the ray misses the plane
/// (parallel, or the plane behind the camera). Returns world x y, m.
Eigen::Vector2d pixel_to_table(const geometry::Camera& camera, const Eigen::Vector2d& pixel,
                               double plane_height = 0.0);
/// An image push as a table push: both ends back-projected onto the table top (eqs 3.13-3.17).
TablePush to_table(const geometry::Camera& camera, const ImagePush& push);

/// How the pusher gets to a push and away from it: lowered at `start`, pushed, lifted at `end`.
struct PushMotionOptions {
  double rate_hz = 500;      ///< control rate of the joint samples, Hz
  double lift = 0.06;        ///< how far the pusher goes up before and after the push, m
  double lift_speed = 0.10;  ///< speed of lowering and lifting, m/s
  IkOptions ik;              ///< pusher pointing down where reachable (pitch free beyond)
  /// Fastest joint motion accepted between samples, rad/s (TrackOptions::max_joint_speed): the
  /// pitch of the pusher turns fast where the reach for a pusher pointing down ends.
  double max_joint_speed = 30;
  /// Turn the roll j5 (it does not move the tip) so that the gripper's jaws, which lie on either
  /// side of the pusher along the last link's y axis, lie across the push, beside the pusher,
  /// at the push's middle: fingers_across_roll. Off: j5 keeps q_rest's value (the jaws lie
  /// across the arm's radius, so they are ahead of and behind the pusher in a push across it).
  /// A push whose TablePush::jaws is not kRobot goes by that instead.
  bool roll_across = false;
  /// Throws Error when an option is out of range.
  void validate() const;
};

/// The roll j5 (rad, within its limits, the nearer to q's j5 of the two) that turns the last
/// link's y axis (the line through both jaws) perpendicular to the table direction `direction`
/// (any length > 0), with j1..j4 of q. Where the link points straight down every other roll
/// leaves the jaws' line a component along `direction`; elsewhere this is the roll that
/// minimises it. Throws Error for a zero or non-finite direction.
double fingers_across_roll(ArmState& state, const JointVector& q, const Eigen::Vector2d& direction);

/// The roll j5 (rad, within its limits, the nearer to q's j5 of the two) that turns the last
/// link's y axis (the line through both jaws) along the table direction `direction` (any length
/// > 0), with j1..j4 of q: the jaws ahead of and behind the pusher. Throws Error for a zero or
/// non-finite direction.
double fingers_along_roll(ArmState& state, const JointVector& q, const Eigen::Vector2d& direction);

/// The joint samples of one push: lower from `lift` above the start, push, lift at the end.
struct PushMotion {
  JointVector q_above_start = JointVector::Zero();  ///< where the transit must bring the arm
  JointTrajectory joints;                           ///< lower, push, lift, at rate_hz
  int push_begin = 0;  ///< first sample of the push proper (after lowering)
  int push_end = 0;    ///< first sample of the lift
};

/// The inverse kinematics (eqs 3.4-3.6, Appendix A) of a push, sampled at the control rate, from
/// `q_rest` (the current joints). Throws Error naming the point when any part of the push is out
/// of the arm's reach or its joint limits (robot::solve_ik's messages); never returns NaN.
PushMotion plan_push_motion(ArmState& state, const TablePush& push, const JointVector& q_rest,
                            const PushMotionOptions& options = {});

/// Whether the pusher can reach table point `xy` at `height` (solve_ik succeeds from `q_rest`).
bool reachable(ArmState& state, const Eigen::Vector2d& xy, double height, const JointVector& q_rest,
               const IkOptions& ik = {});

/// Where a push's episode goes and how it is recorded.
struct PushRecording {
  std::filesystem::path episode_dir;  ///< the episode directory to write; empty: none written
  double fps = 25;                    ///< frame rate of the episode
  bool overwrite = false;             ///< replace an existing episode directory
  core::Provenance run;               ///< provenance written into episode.json
};

/// What happened during a push, as the robot knows it (no ground truth).
struct PushReport {
  TablePush push;                     ///< the push executed (table frame)
  std::filesystem::path episode_dir;  ///< the episode written, or empty
  int frames = 0;                     ///< frames the camera took during the push
  bool touched = false;               ///< the touch signal was on in some frame
  std::optional<int> first_touch_frame;
  double seconds = 0;  ///< the robot's time the push took, s
  /// The hand, lifted after the push, still touched the pushed object (one taller than the lift)
  /// and first backed away along the push before going back.
  bool backed_away = false;
  /// No way back met no object: the arm was put at its rest pose at once (a simulator's
  /// fallback; a real arm would stop and ask for help).
  bool parked_at_once = false;
  std::string message;
};

/// A robot: a camera over a table and an arm that pushes. Implementations: sim::SimulatedRobot;
/// a driver for a real arm (see the top of this file for what it must provide).
class Robot {
 public:
  Robot() = default;
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;
  Robot(Robot&&) = delete;
  Robot& operator=(Robot&&) = delete;
  virtual ~Robot() = default;

  /// The current image, arm state and calibration.
  virtual Look look() = 0;
  /// The camera calibration (constant while the robot runs).
  [[nodiscard]] virtual geometry::Camera camera() const = 0;
  /// The arm's kinematic model (for planning: reachability through inverse kinematics).
  [[nodiscard]] virtual const Arm& arm() const = 0;
  /// The arm's current joint angles, rad.
  [[nodiscard]] virtual JointVector joints() const = 0;

  /// Executes `push`: a transit to above its start, lowering, the straight push at its height,
  /// lifting (plan_push_motion), recording what the camera sees as an episode when
  /// recording.episode_dir is set (frames, arm.csv with the robot's touch flag, calib.yml; no
  /// ground truth). Throws Error for an invalid or unreachable push (nothing moves then) or an
  /// episode directory that exists (unless overwrite).
  virtual PushReport push(const TablePush& push, const PushRecording& recording) = 0;
  /// Keeps the arm where it is (its joint targets unchanged) for `seconds` of the robot's clock
  /// while the world goes on: whatever moves by itself (people, a distractor behind the table)
  /// moves on; nothing is recorded. A real driver sleeps. Used to tell things that move by
  /// themselves from objects at rest (LearnOptions::moving_wait). Throws Error for a time that
  /// is not finite, negative or over 10 s (nothing happens then).
  virtual void hold_still(double seconds) = 0;
  /// The same push given in image pixels: back-projected onto the table (to_table), then push().
  PushReport push_image(const ImagePush& push, const PushRecording& recording) {
    return this->push(to_table(camera(), push), recording);
  }
};

}  // namespace proprio::robot
