#pragma once
// What stands behind the table (thesis 5.1), shared by the episode recorder (sim/recorder.hpp)
// and the persistent table behind robot::Robot (sim/simulated_robot.hpp): nothing (a plain
// view of the table and the floor), a photograph on a wall behind the table, or a video of people
// walking shown on that wall frame by frame with moving distractor objects sliding about in front
// of it.
//
// Frames: world = robot base frame (metres, z up, +x forward, table top z = 0).

#include <Eigen/Core>
#include <filesystem>

#include "proprio/core/fields.hpp"
#include "proprio/sim/scene_description.hpp"

namespace proprio::sim {

enum class Background {
  kPlain,   ///< no backdrop
  kPhoto,   ///< a photograph on the backdrop
  kMoving,  ///< a video on the backdrop, advancing with the simulated time, and distractors
};
inline constexpr core::ChoiceNames<Background, 3> kBackgroundNames{
    {{"plain", Background::kPlain},
     {"photo", Background::kPhoto},
     {"moving", Background::kMoving}}};

/// vtest.avi of the opencv-doc samples (people walking).
std::filesystem::path default_background_video();
/// leuvenA.jpg of the opencv-doc samples (a street), the default scene's backdrop.
std::filesystem::path default_background_photo();

/// Where the backdrop stands and where the distractors slide (world, m).
struct BackdropLayout {
  Eigen::Vector3d center{0.30, 0.56, 0.30};  ///< centre of the vertical backdrop plane
  Eigen::Vector2d size{1.8, 0.9};            ///< its width and height
  int texture_width = 384;                   ///< texels (the video's 4:3 aspect)
  int texture_height = 288;
  /// Distractors slide along x = centre_x + amplitude sin(...) on the line y = line_y.
  double line_y = 0.46;
  double centre_x = 0.35;
  double amplitude = 0.30;
  /// Distractors are felt by the table only (they pass through the objects and the arm): their
  /// script, not contacts, moves them (the robot's table; the recorder keeps them solid).
  bool ghost_distractors = false;
};

/// The recorder's layout: the backdrop just behind the table, low enough that its camera sees
/// the middle of the picture (where vtest.avi's people walk).
BackdropLayout recording_backdrop_layout();

/// Sets scene.backdrop for `background`: disabled (kPlain), or the plane of `layout` showing
/// `photo` (kPhoto; kMoving: grey until the video's first frame is shown).
void set_backdrop(SceneDescription& scene, Background background, const BackdropLayout& layout,
                  const std::filesystem::path& photo);

}  // namespace proprio::sim
