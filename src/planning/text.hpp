#pragma once
// Message building (core/text.hpp) for the planning module.

#include "proprio/core/text.hpp"

namespace proprio::planning::detail {

using core::cat;
using core::num;

}  // namespace proprio::planning::detail
