#pragma once
// The MuJoCo that this build links, for provenance. It lives here, in the lowest module that uses
// MuJoCo, so that core (and topics above it) stay free of MuJoCo.

#include <string>

namespace proprio::robot {

/// MuJoCo's version string, e.g. "2.2.2" (for core::Provenance::mujoco_version).
std::string mujoco_version();

}  // namespace proprio::robot
