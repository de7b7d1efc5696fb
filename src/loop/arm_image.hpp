#pragma once
// The arm's own image in a push's frame, as the robot knows it (its kinematics and the frame's
// joint angles, no ground truth): the learners of the loop module cut it out of their views,
// since features there move with the arm and belong to no object.
#include <opencv2/core.hpp>
#include <optional>

#include "proprio/episode/episode.hpp"
#include "proprio/robot/arm.hpp"

namespace proprio::loop::detail {

/// Frame `i` of `e`: every link of the arm's kinematic chain (base body to the end effector,
/// placed by the frame's joint angles through `arm`'s kinematics, `state` made on first use)
/// drawn through `e`'s camera as a band 6 cm half width, the pusher and the base's column; 255
/// on the arm, CV_8U of `size`. Without joint angles in arm.csv, a band 3.5 cm half width from
/// the end effector's image toward the base.
cv::Mat1b arm_image_mask(const episode::Episode& e, int i, cv::Size size, const robot::Arm& arm,
                         std::optional<robot::ArmState>& state);

}  // namespace proprio::loop::detail
