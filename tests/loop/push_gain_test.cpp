// The closed push loop's correction gain (loop::correction_gain, PushOptions::min_gain and
// max_gain): what the next push asks after one that under- or overshot.
#include <gtest/gtest.h>

#include <cmath>

#include "proprio/core/error.hpp"
#include "proprio/loop/push_run.hpp"

namespace proprio::loop {
namespace {

TEST(PushGain, AnOvershootAsksLessNextTimeDownToTheLeastGain) {
  const Eigen::Vector2d asked(0.04, 0.0);
  // Moved 1.25 times what it asked (it slid on): the next push asks 0.8 of the remaining way
  // with min_gain 0.5; by the default (1) never less than the remaining way.
  EXPECT_NEAR(correction_gain(asked, {0.05, 0.004}, 0.5, 2.0), 0.8, 1e-12);
  EXPECT_NEAR(correction_gain(asked, {0.05, 0.004}, 1.0, 1.0), 1.0, 1e-12);
  // Three times (it rolled): held at the least gain.
  EXPECT_NEAR(correction_gain(asked, {0.12, 0.0}, 0.5, 2.0), 0.5, 1e-12);
  // Half (it turned or the pusher met it late): twice, up to max_gain.
  EXPECT_NEAR(correction_gain(asked, {0.02, -0.01}, 0.5, 2.0), 2.0, 1e-12);
  EXPECT_NEAR(correction_gain(asked, {0.02, 0.0}, 0.5, 1.5), 1.5, 1e-12);
  // Only the share along the asked direction counts; a move backwards is max_gain.
  EXPECT_NEAR(correction_gain({0.0, 0.03}, {0.03, 0.03}, 0.5, 2.0), 1.0, 1e-12);
  EXPECT_NEAR(correction_gain(asked, {-0.01, 0.0}, 0.5, 2.0), 2.0, 1e-12);
  EXPECT_THROW((void)correction_gain({0.0, 0.0}, {0.01, 0.0}, 0.5, 2.0), Error);
  EXPECT_THROW((void)correction_gain(asked, {std::nan(""), 0.0}, 0.5, 2.0), Error);
  EXPECT_THROW((void)correction_gain(asked, {0.01, 0.0}, 2.0, 1.0), Error);
}

TEST(PushGain, TheLeastGainIsAnOptionBoundedBelowOne) {
  PushOptions o;
  EXPECT_EQ(o.min_gain, 1.0);  // the default: as before
  o.min_gain = 0.5;
  EXPECT_NO_THROW(o.validate());
  o.min_gain = 1.5;
  EXPECT_THROW(o.validate(), Error);
  PushEvaluationOptions e;
  e.min_gain = 0.1;
  EXPECT_THROW(e.validate(), Error);
}

}  // namespace
}  // namespace proprio::loop
