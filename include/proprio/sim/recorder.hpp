#pragma once
// Recording simulated episodes (thesis 5.1-5.2): a scenario puts objects on the table, the arm
// pushes the target object along a straight line parallel to the table, and every frame is
// written in the episode format (docs/formats/episode.md) with exact ground truth: RGB, 16-bit
// object-id masks, joint angles, end-effector position and pixel, and whether the arm touched
// the target in any physics step since the previous frame.
//
// Frames: world = robot base frame (metres, z up, +x forward, table top z = 0).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_description.hpp"

namespace proprio::sim {

/// Scenario names record_episode knows: "push" (a straight push through the object's centre,
/// thesis 5.1), "push-rotate" (the same push offset sideways, so the object turns, 5.2),
/// "clutter" (the push among at least 6 objects placed at random), "scatter" (the push while at
/// least 5 other objects slide about behind it, leaving and entering the view, 6.3.3; with
/// RecordOptions::scatter_objects, exactly those objects, wandering over the table) and
/// "hold-3d" (the object held under the pusher and carried along a 3D curve, 5.2: a MuJoCo weld
/// equality constraint between the arm's last link and the object, switched on at the start,
/// stands in for the grip, so the physics carries it; every frame counts as touching).
std::vector<std::string> known_scenarios();

/// What a recording records of its options (episode.json's provenance.switches, the records of
/// `sim record` and `sim dataset`): the scene and the disturbances switched on.
struct RecordSwitches {
  std::string object;      ///< the target, or "(scene file)"
  std::string background;  ///< "static" or "moving"
  int distractors = 0;
  int clutter = 0;
  std::optional<std::vector<std::string>> scatter_objects;  ///< when given
  std::optional<bool> scatter_in_view;                      ///< with scatter_objects
  double push_speed = 0;
  double approach = 0;
  int width = 0;
  int height = 0;
  double fps = 0;
  bool shadows = false;
  bool reflections = false;
  bool camera_shake = false;
  bool lighting_change = false;
  bool nudge_neighbour = false;
  double noise = 0;
  bool motion_blur = false;
  bool stereo = false;
  std::optional<double> stereo_baseline;  ///< with stereo (null without)
  bool depth = false;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.object, {"object", "The target (catalogue name), or (scene file)"});
    v(self.background, {"background", "static or moving"});
    v(self.distractors, {"distractors", "Distractors sliding behind the target"});
    v(self.clutter, {"clutter", "Other objects placed at random"});
    v(self.scatter_objects, {"scatter_objects", "scatter: the scene's objects"});
    v(self.scatter_in_view, {"scatter_in_view", "scatter: the walkers keep in view"});
    v(self.push_speed, {"push_speed", "Mean speed of the push, m/s"});
    v(self.approach, {"approach", "Pusher tip to the target's back face at the start, m"});
    v(self.width, {"width", "Image width, px"});
    v(self.height, {"height", "Image height, px"});
    v(self.fps, {"fps", "Frame rate"});
    v(self.shadows, {"shadows", "Shadows rendered"});
    v(self.reflections, {"reflections", "Reflections rendered"});
    v(self.camera_shake, {"camera_shake", "The camera trembles"});
    v(self.lighting_change, {"lighting_change", "The main light jumps half-way"});
    v(self.nudge_neighbour, {"nudge_neighbour", "A neighbour is shoved during the push"});
    v(self.noise, {"noise", "Image noise std, grey levels"});
    v(self.motion_blur, {"motion_blur", "Frames average 4 instants"});
    v(self.stereo, {"stereo", "A stereo pair"});
    v(core::or_null(self.stereo_baseline), {"stereo_baseline", "Camera centres apart, m"});
    v(self.depth, {"depth", "Depth images"});
  }
};

struct RecordOptions {
  std::string scenario = "push";
  std::string object = "mug";  ///< the target, a catalogue name
  /// Moving background (thesis 5.1): the backdrop shows `background_video` frame by frame and
  /// `distractors` objects slide back and forth behind the target.
  bool moving_background = false;
  std::filesystem::path background_video = default_background_video();
  /// Moving distractor objects sliding about behind the target; none = 2 with a moving
  /// background, 0 with a static one.
  std::optional<int> distractors;
  int clutter = 3;  ///< other objects placed at random (by seed), never in the push path
  /// scatter: the scene's objects (catalogue names), the target among them; the others wander
  /// over the table at random (ScenarioPlan::walkers), leaving and entering the camera's view,
  /// as in thesis 6.3.3 ("objects moved about at random"). Empty: the target and
  /// max(clutter, 5) other objects drawn at random, sliding along x (ScenarioPlan::sliders).
  std::vector<std::string> scatter_objects;
  /// scatter objects: the walkers keep inside the camera's view of the table (thesis 6.3.3's
  /// first video, "none of the objects leave the camera's field of view"; the arm may still
  /// pass in front of them). Off: they leave it and come back (the second video).
  bool scatter_in_view = false;
  std::uint64_t seed = 7;
  int width = 640;  ///< image size, pixels
  int height = 480;
  double fps = 25.0;          ///< frame rate; 1 / (fps * timestep) must be a whole number of steps
  double push_speed = 0.04;   ///< mean speed of the push, m/s
  double still_before = 0.4;  ///< seconds recorded before the arm moves
  double still_after = 0.4;   ///< and after it stops
  double pusher_height = 0.015;  ///< height of the pusher tip above the table, m
  /// Distance from the pusher tip to the target's back face at the start, m (0.025-0.15): the
  /// arm's motion before the touch is the evidence that removes it (eq 4.18). Shortened, down
  /// to 0.025, for targets too long to be pushed within reach after it.
  double approach = 0.06;
  bool shadows = false;  ///< off: about twice the frame rate in software GL
  bool reflections = false;
  bool overwrite = false;  ///< replace an existing episode directory
  /// Stop after this many frames (none: the whole push and the still times).
  std::optional<int> max_frames;

  // Disturbances (thesis 5.1), each recorded in episode.json's provenance.switches.
  /// The camera trembles: its rendered pose gets a random offset (up to 4 mm, 0.4 degrees) each
  /// frame; calib.yml keeps the nominal pose.
  bool camera_shake = false;
  /// Half-way through the episode the main light jumps to another place and direction.
  bool lighting_change = false;
  /// A neighbouring object beside the push path is shoved 5 cm sideways during the push (by
  /// something other than the arm; role "distractor").
  bool nudge_neighbour = false;
  double noise = 0.0;            ///< standard deviation of Gaussian image noise, grey levels
  bool motion_blur = false;      ///< each frame averages renders at 4 instants of its interval
  bool stereo = false;           ///< a stereo pair: frames_right/, calib_right.yml
  double stereo_baseline = 0.1;  ///< distance between the two camera centres, m (stereo)
  bool depth = false;            ///< depth/ images (16-bit millimetres)

  /// vtest.avi of the opencv-doc samples (people walking).
  static std::filesystem::path default_background_video();
  /// Throws Error naming the option that is out of range or unknown (scenario).
  void validate() const;
  /// The number of distractors in effect (see `distractors`).
  [[nodiscard]] int distractor_count() const;
  /// The switches (episode.json's provenance.switches: core::fields_to_json of them).
  [[nodiscard]] RecordSwitches switches() const;
};

/// The scene and the push that record_episode plays, computed from the options alone
/// (deterministic in the seed).
struct ScenarioPlan {
  SceneDescription scene;
  std::string target;                    ///< instance name of the target object
  std::vector<std::string> distractors;  ///< instance names of the moving distractors
  std::string neighbour;  ///< instance name of the object nudged (nudge_neighbour), else empty
  /// scatter: objects sliding along x at their own speed (m/s), wrapping round [-0.5, 1.0] m.
  struct Slider {
    std::string name;
    double x0 = 0, y = 0, speed = 0;
  };
  std::vector<Slider> sliders;
  /// scatter with chosen objects: objects that wander over the table, a random walk of heading
  /// and speed (record_episode advances it each frame from a stream of the seed), bouncing off
  /// each other and off the walls of [walk_min, walk_max], a box wider than the camera's view
  /// so that they leave the view and come back. Each stays in y >= its own `y_min`, behind the
  /// push corridor.
  struct Walker {
    std::string name;
    Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< start, world x y, m
    double heading = 0;                                  ///< direction of motion, rad from +x
    double speed = 0;                                    ///< m/s
    double yaw = 0;                                      ///< rad
    double radius = 0;                                   ///< footprint radius, m
    double y_min = 0;                                    ///< m
  };
  std::vector<Walker> walkers;
  Eigen::Vector2d walk_min = Eigen::Vector2d::Zero(), walk_max = Eigen::Vector2d::Zero();
  /// hold-3d: the target is grasped (scene.grasp_object) and carried on the quadratic Bezier
  /// push_start, via, push_end.
  bool held = false;
  Eigen::Vector3d via = Eigen::Vector3d::Zero();
  Eigen::Vector3d push_start = Eigen::Vector3d::Zero();  ///< pusher tip, world, m
  Eigen::Vector3d push_end = Eigen::Vector3d::Zero();
};

/// Builds the scene of a scenario: the target at yaw 0 placed so that the whole push stays inside
/// the arm's reach with the pusher pointing down (0.10-0.33 m from the base axis), clutter placed
/// at random outside the push corridor and not in front of it, distractors behind; scatter:
/// sliders, or walkers started at random (non-overlapping) places in the camera's view. Throws
/// Error for an unknown scenario or object, or scatter objects that are unknown, repeated, do not
/// include the target, or are given for another scenario.
ScenarioPlan plan_scenario(const RecordOptions& options, const ObjectCatalogue& catalogue);

class World;
/// World::build of a plan of `options`; when the scenario is a scene file, an error building its
/// world (MuJoCo's compiler refusing an object) names the scene file.
World build_scenario_world(const ScenarioPlan& plan, const ObjectCatalogue& catalogue,
                           const RecordOptions& options);

struct RecordSummary {
  int frames = 0;
  double seconds = 0.0;  ///< wall clock, physics, rendering and writing included
  double fps = 0.0;      ///< frames / seconds
  /// First frame whose `touching` is 1; none when the arm never touched the target.
  std::optional<int> first_touch_frame;
  double target_moved = 0.0;  ///< distance the target's origin moved over the episode, m
  /// Where the wall-clock time went, seconds summed over the episode. The writer runs on a
  /// thread of its own, so `write` overlaps the other stages; `write_wait` is the time the
  /// simulation waited for it.
  struct Timing {
    double setup = 0.0;        ///< scene, world, IK of the whole push, settling, writer set-up
    double physics = 0.0;      ///< physics steps and the scripted object motions
    double backdrop = 0.0;     ///< video frame decoding and texture upload (moving background)
    double render_rgb = 0.0;   ///< colour pass (+ depth, right camera, blur, noise) and read-back
    double render_mask = 0.0;  ///< id-colour pass, read-back and decoding to object ids
    double write = 0.0;        ///< PNG encoding and writing, arm.csv (writer thread)
    double write_wait = 0.0;   ///< simulation thread blocked on a full writer queue
    double finish = 0.0;       ///< episode.json, calib.yml, read-back check, rename
  } timing;
  std::string message;
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

/// Records one episode into `out` (atomically: nothing appears there unless the whole episode
/// was written and reads back). Throws Error for bad options, an unknown object, an unreadable
/// texture or video, an unreachable push, an existing `out` (unless overwrite), or a physics
/// warning.
RecordSummary record_episode(const std::filesystem::path& out, const RecordOptions& options,
                             const core::Provenance& run, const ObjectCatalogue& catalogue);

}  // namespace proprio::sim
