#pragma once
// One row of arm.csv: the arm's state at one frame.
//
// arm.csv columns: frame,t,q1..qN,ee_x,ee_y,ee_z,ee_u,ee_v,touching (docs/formats/episode.md).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace proprio::episode {

struct ArmSample {
  double t = 0.0;     ///< time of the frame, seconds; strictly increasing over an episode
  Eigen::VectorXd q;  ///< joint angles, rad (size = EpisodeInfo::joint_count)
  Eigen::Vector3d ee = Eigen::Vector3d::Zero();  ///< end-effector position, robot frame, metres
  /// End-effector image position, pixels (in the frames as stored); none = project it through
  /// the calibration (Episode::ee_image).
  std::optional<Eigen::Vector2d> ee_image;
  /// The arm touched an object in any physics step (or log sample) since the previous frame.
  bool touching = false;
};

/// arm.csv's header for N joints: frame,t,q1..qN,ee_x,ee_y,ee_z,ee_u,ee_v,touching.
std::vector<std::string> arm_csv_header(int joint_count);

}  // namespace proprio::episode
