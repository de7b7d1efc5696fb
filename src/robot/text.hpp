#pragma once
// Message building for the robot module's errors (core/text.hpp).

#include "proprio/core/text.hpp"

namespace proprio::robot::detail {

using core::cat;
using core::num;

}  // namespace proprio::robot::detail
