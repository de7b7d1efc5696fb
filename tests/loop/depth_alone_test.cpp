// loop::depth_footprints and loop::depth_alone on depth images of boxes ray-cast from an
// oblique camera (as the simulated table's), with blobs made of each box's projected top.
#include "proprio/loop/depth_alone.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../support/box_depth.hpp"
#include "proprio/core/error.hpp"

namespace proprio::loop {
namespace {

// An axis-aligned box standing on the table: footprint centre, half sides, height, m.
using Box = test::DepthBox;

geometry::Camera oblique_camera() {
  return test::look_at_camera(Eigen::Vector3d(0.30, -0.45, 0.80), Eigen::Vector3d(0.30, 0.02, 0.0),
                              300, 320, 240);
}

// A blob of feature points on the tops of `boxes` (a 5 x 5 grid on each top, projected).
planning::PutativeObject blob_on(const geometry::Camera& cam, const std::vector<Box>& boxes) {
  planning::PutativeObject o;
  for (const Box& b : boxes) {
    for (int i = -2; i <= 2; ++i) {
      for (int j = -2; j <= 2; ++j) {
        const Eigen::Vector3d x(b.c.x() + 0.3 * i * b.hx, b.c.y() + 0.3 * j * b.hy, b.h);
        o.pixels.push_back(cam.project(x));
      }
    }
  }
  return o;
}

planning::PlanningView view_of(const geometry::Camera& cam,
                               const std::vector<std::vector<Box>>& blobs) {
  planning::PlanningView v;
  v.camera = cam;
  v.image_size = cv::Size(cam.width, cam.height);
  for (const auto& b : blobs) v.objects.push_back(blob_on(cam, b));
  return v;
}

TEST(DepthAlone, AGapOfFiveCentimetresIsAloneTouchingObjectsAreNot) {
  const geometry::Camera cam = oblique_camera();
  const planning::TableRegion region;
  const Box tall{{0.30, 0.00}, 0.03, 0.03, 0.15};
  // Side by side across the view, 5 cm of table between them.
  {
    const Box low{{0.41, 0.00}, 0.03, 0.03, 0.04};
    const cv::Mat1f depth = test::render_boxes_depth(cam, {tall, low});
    const DepthFootprints fp = depth_footprints(depth, cam, region);
    ASSERT_EQ(fp.parts.size(), 2U);
    const planning::PlanningView view = view_of(cam, {{tall}, {low}});
    const DepthAlone a = depth_alone(fp, view, 0, 0.04);
    EXPECT_TRUE(a.measured);
    EXPECT_FALSE(a.merged);
    EXPECT_NEAR(a.gap, 0.05, 0.006);
    EXPECT_TRUE(a.alone) << a.why;
    ASSERT_TRUE(a.blob_gaps[1].has_value());
    EXPECT_NEAR(*a.blob_gaps[1], 0.05, 0.006);
    EXPECT_FALSE(a.blob_gaps[0].has_value());
    // The low box's check sees the same gap; a clearance of 10 cm is not met.
    EXPECT_NEAR(depth_alone(fp, view, 1, 0.04).gap, 0.05, 0.006);
    EXPECT_FALSE(depth_alone(fp, view, 0, 0.10).alone);
  }
  // Touching (no gap), a tall box beside a low one: their front faces meet, one surface, and
  // the low box's blob lies on the tall one's footprint: gap 0, not alone.
  {
    const Box low{{0.36, 0.00}, 0.03, 0.03, 0.04};
    const cv::Mat1f depth = test::render_boxes_depth(cam, {tall, low});
    const DepthFootprints fp = depth_footprints(depth, cam, region);
    const DepthAlone a = depth_alone(fp, view_of(cam, {{tall}, {low}}), 0, 0.04);
    EXPECT_TRUE(a.measured);
    EXPECT_LT(a.gap, 0.005);
    EXPECT_FALSE(a.alone) << a.why;
    EXPECT_FALSE(depth_alone(fp, view_of(cam, {{tall}, {low}}), 1, 0.04).alone);
  }
  // A low box 2.5 cm in front of a tall one: two footprints 2.5 cm apart. Seen as one blob,
  // that blob lies on both: merged, not alone.
  {
    const Box front{{0.30, -0.10}, 0.03, 0.03, 0.04};
    const Box behind{{0.30, -0.015}, 0.03, 0.03, 0.15};
    const cv::Mat1f depth = test::render_boxes_depth(cam, {front, behind});
    const DepthFootprints fp = depth_footprints(depth, cam, region);
    ASSERT_EQ(fp.parts.size(), 2U);
    const DepthAlone a = depth_alone(fp, view_of(cam, {{front}, {behind}}), 0, 0.04);
    EXPECT_NEAR(a.gap, 0.025, 0.005);
    EXPECT_FALSE(a.alone) << a.why;
    const DepthAlone one = depth_alone(fp, view_of(cam, {{front, behind}}), 0, 0.01);
    EXPECT_TRUE(one.merged);
    EXPECT_FALSE(one.alone) << one.why;
  }
  // Parts of one object: 8 mm apart (the table between hidden behind the low box), separated by
  // the depth jump from its top to the tall box's face, but one blob owns both and they are
  // nearer than part_gap 1.5 cm: one object, alone; two blobs on them are two objects 8 mm apart,
  // not alone. Without the depth jump (join as wide as the scene) they are one footprint.
  {
    const Box front{{0.30, -0.10}, 0.03, 0.03, 0.04};
    const Box behind{{0.30, -0.032}, 0.03, 0.03, 0.15};
    const cv::Mat1f depth = test::render_boxes_depth(cam, {front, behind});
    const DepthFootprints fp = depth_footprints(depth, cam, region);
    ASSERT_EQ(fp.parts.size(), 2U);
    DepthAloneOptions parts;
    parts.part_gap = 0.015;
    const DepthAlone one = depth_alone(fp, view_of(cam, {{front, behind}}), 0, 0.1, parts);
    EXPECT_FALSE(one.merged);
    EXPECT_TRUE(one.alone) << one.why;
    // part_gap 0 (the default): the second part carries half the blob's features: merged.
    EXPECT_TRUE(depth_alone(fp, view_of(cam, {{front, behind}}), 0, 0.1).merged);
    const DepthAlone two = depth_alone(fp, view_of(cam, {{front}, {behind}}), 0, 0.1);
    EXPECT_LT(two.gap, 0.015);
    EXPECT_FALSE(two.alone) << two.why;
    DepthFootprintOptions wide;
    wide.join = 0.2;
    EXPECT_EQ(depth_footprints(depth, cam, region, wide).parts.size(), 1U);
  }
  // Touching boxes of one height make one surface: two blobs on it are not alone (gap 0).
  {
    const Box twin{{0.36, 0.00}, 0.03, 0.03, 0.15};
    const cv::Mat1f depth = test::render_boxes_depth(cam, {tall, twin});
    const DepthFootprints fp = depth_footprints(depth, cam, region);
    ASSERT_EQ(fp.parts.size(), 1U);
    const DepthAlone a = depth_alone(fp, view_of(cam, {{tall}, {twin}}), 0, 0.04);
    EXPECT_EQ(a.gap, 0.0);
    ASSERT_TRUE(a.blob_gaps[1].has_value());
    EXPECT_EQ(*a.blob_gaps[1], 0.0);
    EXPECT_FALSE(a.alone);
  }
  // One box alone: its footprint is the box's, no other footprint, alone.
  {
    const cv::Mat1f depth = test::render_boxes_depth(cam, {tall});
    const DepthFootprints fp = depth_footprints(depth, cam, region);
    ASSERT_EQ(fp.parts.size(), 1U);
    EXPECT_NEAR(fp.parts[0].height, 0.15, 0.005);
    const DepthAlone a = depth_alone(fp, view_of(cam, {{tall}}), 0, 0.10);
    EXPECT_TRUE(a.alone) << a.why;
    EXPECT_TRUE(std::isinf(a.gap));
  }
}

TEST(DepthAlone, NoDepthIsNotMeasuredAndBadInputsThrow) {
  const geometry::Camera cam = oblique_camera();
  const planning::TableRegion region;
  const Box b{{0.30, 0.00}, 0.03, 0.03, 0.05};
  const planning::PlanningView view = view_of(cam, {{b}});
  // No depth image, or a bare table: no footprints, the check is not measured (and not alone).
  const DepthFootprints none = depth_footprints(cv::Mat(), cam, region);
  EXPECT_TRUE(none.parts.empty());
  const DepthAlone a = depth_alone(none, view, 0, 0.1);
  EXPECT_FALSE(a.measured);
  EXPECT_FALSE(a.alone);
  EXPECT_TRUE(depth_footprints(test::render_boxes_depth(cam, {}), cam, region).parts.empty());
  // Bad inputs.
  const DepthFootprints fp = depth_footprints(test::render_boxes_depth(cam, {b}), cam, region);
  EXPECT_THROW((void)depth_alone(fp, view, 1, 0.1), Error);
  EXPECT_THROW((void)depth_alone(fp, view, -1, 0.1), Error);
  EXPECT_THROW((void)depth_alone(fp, view, 0, 0.0), Error);
  EXPECT_THROW((void)depth_alone(fp, view, 0, std::nan("")), Error);
  DepthAloneOptions bad;
  bad.part_gap = -0.01;
  EXPECT_THROW((void)depth_alone(fp, view, 0, 0.1, bad), Error);
  bad.part_gap = 0.2;
  EXPECT_THROW((void)depth_alone(fp, view, 0, 0.1, bad), Error);
  EXPECT_THROW((void)depth_footprints(cv::Mat1f(10, 10, 1.0F), cam, region), Error);
  EXPECT_THROW((void)depth_footprints(cv::Mat(240, 320, CV_16U), cam, region), Error);
  DepthFootprintOptions o;
  o.join = 0;
  EXPECT_THROW((void)depth_footprints(test::render_boxes_depth(cam, {b}), cam, region, o), Error);
  o = {};
  o.least_pixels = 0;
  EXPECT_THROW((void)depth_footprints(test::render_boxes_depth(cam, {b}), cam, region, o), Error);
  o = {};
  o.least_height = -0.01;
  EXPECT_THROW((void)depth_footprints(test::render_boxes_depth(cam, {b}), cam, region, o), Error);
}

}  // namespace
}  // namespace proprio::loop
