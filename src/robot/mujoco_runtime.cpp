#include "proprio/robot/mujoco_runtime.hpp"

#include <mujoco/mujoco.h>

namespace proprio::robot {

std::string mujoco_version() { return mj_versionString(); }

}  // namespace proprio::robot
