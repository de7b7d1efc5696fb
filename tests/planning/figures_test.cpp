// The figures render (sizes, something drawn) and refuse what they cannot draw.
#include "proprio/planning/figures.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "planning_test_support.hpp"

namespace proprio::planning {
namespace {
using testing::internal_error_of;
using testing::simulator;

// Fraction of pixels that are not white.
double ink(const cv::Mat& img) {
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  return 1.0 - cv::countNonZero(grey >= 250) / static_cast<double>(grey.total());
}

TEST(Figures, EnergyGridHasOnePanelPerGamma) {
  const cv::Mat img = draw_energy_grid(testing::grid_model()->costs());
  EXPECT_EQ(img.type(), CV_8UC3);
  EXPECT_GT(img.cols, 900);
  EXPECT_GT(ink(img), 0.2);
}

TEST(Figures, InterceptionAndNoiseChoiceDraw) {
  TrialOptions o;
  o.noise_cm = 1.0;
  o.record = true;
  core::Rng rng(2);
  const GridSpec& g = simulator().model().grid();
  const double t_plan = simulator().plan_time(o);
  const TargetMotion target = random_target(g, t_plan, o.scenario, rng);
  const TrialResult t = simulator().run(target, o, 3);
  const cv::Mat a = draw_interception(t, g);
  EXPECT_GT(ink(a), 0.02);
  std::vector<NoiseChoice> choices;
  for (PriorMode m : {PriorMode::kBoth, PriorMode::kEnergy, PriorMode::kPrecision}) {
    for (double n : {0.0, 1.0, 2.0}) choices.push_back({n, m, 1.5 - 0.1 * n, 0.05, 3});
  }
  const cv::Mat b = draw_noise_choices(target, t_plan, g, choices);
  EXPECT_GT(ink(b), 0.02);
  TrialResult unrecorded = t;
  unrecorded.record = {};
  EXPECT_NE(internal_error_of([&] { draw_interception(unrecorded, g); }).find("not recorded"),
            std::string::npos);
  EXPECT_NE(
      internal_error_of([&] { draw_noise_choices(target, t_plan, g, {}); }).find("no choices"),
      std::string::npos);
}

}  // namespace
}  // namespace proprio::planning
