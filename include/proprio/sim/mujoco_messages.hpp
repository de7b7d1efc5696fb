#pragma once
// MuJoCo's warnings and errors through the project's logging. MuJoCo's default handlers print to
// stdout and append to MUJOCO_LOG.TXT in the working directory, and its default error handler
// exits the process; a library must do neither behind its user's back.

namespace proprio::sim {

/// Installs MuJoCo's user warning and error handlers (mju_user_warning, mju_user_error) once per
/// process; thread-safe, and every World and Renderer calls it. A warning is logged (spdlog,
/// level warn) and counted. An error is logged and aborts: MuJoCo requires that the error handler
/// not return, and a C++ exception thrown through MuJoCo's C frames is undefined behaviour
/// (MuJoCo's own Python bindings longjmp out of the handler instead, python/mujoco/errors.h).
/// Recoverable problems are not errors in MuJoCo: a bad model is refused by mj_loadXML's error
/// buffer (an Error here) and physics trouble is a warning, which World::step turns into an
/// Error.
void install_mujoco_handlers();

/// MuJoCo warnings logged since the process started (after install_mujoco_handlers). The tests
/// of the simulator fail when it grows.
[[nodiscard]] int mujoco_warning_count();

}  // namespace proprio::sim
