// The simulated robot-camera calibration (thesis 3.2.3).
#include "proprio/sim/calibration.hpp"

#include <gtest/gtest.h>

#include "proprio/core/error.hpp"

namespace proprio::sim {
namespace {

TEST(SimCalibration, SmallGridReachesSubPixelRms) {
  SimCalibrationOptions o;
  o.grid = 3;
  o.width = 320;
  o.height = 240;
  const SimCalibrationResult r = calibrate_simulated(o);
  EXPECT_GE(r.summary.used, 20) << r.summary.message;
  EXPECT_LT(r.dlt.rms_px, 1.0);
  // The marker is found where the end-effector projects (no bias from the finger hiding it).
  EXPECT_LT(r.true_error_px, 0.3);
  // The fitted camera is the true one: same optical centre to a few millimetres.
  EXPECT_LT((r.dlt.camera.center() - r.true_camera.center()).norm(), 0.02);
}

TEST(SimCalibration, BadOptionsAreErrors) {
  SimCalibrationOptions o;
  o.grid = 1;
  EXPECT_THROW(calibrate_simulated(o), Error);
  o = {};
  o.lo = o.hi;
  EXPECT_THROW(calibrate_simulated(o), Error);
}

}  // namespace
}  // namespace proprio::sim
