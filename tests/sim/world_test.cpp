// World: physics, object and arm poses, contacts, warnings, determinism. No rendering here.
#include "proprio/sim/world.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "proprio/core/error.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {

// A pose of the arm with the pusher tip 4 cm above the table, 0.35 m out (found by forward
// kinematics on data/models/arm.xml); j1 turns it about the base.
robot::JointVector low_pose(double yaw) {
  robot::JointVector q;
  q << yaw, 0.4, -0.8, -0.9, 0.0;
  return q;
}

World all_objects_world() {
  SceneDescription d = test::small_scene();
  test::add_all_objects(d);
  return World::build(d, ObjectCatalogue::load_default());
}

TEST(World, ObjectsStartWhereTheDescriptionPutsThemAndRest) {
  World w = all_objects_world();
  ASSERT_EQ(w.objects().size(), 10U);
  ASSERT_TRUE(w.has_arm());
  for (const SceneObject& o : w.objects()) {
    const Pose p = w.object_pose(o.id);
    // The MJCF carries 9 significant digits.
    EXPECT_LT((p.translation() - o.initial_position).norm(), 1e-8) << o.name;
    const Eigen::Matrix3d yaw =
        Eigen::AngleAxisd(o.initial_yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_LT((p.rotation() - yaw).norm(), 1e-7) << o.name;
    EXPECT_EQ(w.body_object_id(mj_name2id(&w.model(), mjOBJ_BODY, o.body.c_str())), o.id);
  }
  // Half a second with the arm held still: nothing should move by more than a millimetre.
  w.set_arm_configuration(w.arm_joints());
  w.step(250);
  EXPECT_TRUE(w.warnings().empty());
  for (const SceneObject& o : w.objects()) {
    EXPECT_LT((w.object_pose(o.id).translation() - o.initial_position).norm(), 1e-3) << o.name;
    EXPECT_LT(w.object_velocity(o.id).norm(), 1e-2) << o.name;
  }
  EXPECT_NEAR(w.time(), 250 * w.timestep(), 1e-9);
}

TEST(World, IdsCoverArmObjectsAndBackground) {
  World w = all_objects_world();
  const mjModel& m = w.model();
  EXPECT_EQ(w.geom_object_id(mj_name2id(&m, mjOBJ_GEOM, "marker")), kArmId);
  EXPECT_EQ(w.geom_object_id(mj_name2id(&m, mjOBJ_GEOM, "arm_base_geom")), kArmId);
  EXPECT_EQ(w.geom_object_id(mj_name2id(&m, mjOBJ_GEOM, "table_top")), kBackgroundId);
  EXPECT_EQ(w.geom_object_id(mj_name2id(&m, mjOBJ_GEOM, "backdrop")), kBackgroundId);
  const SceneObject& mug = w.object("mug");
  EXPECT_EQ(w.geoms_of(mug.id).size(), mug.type.parts.size());
  const std::vector<LinkPose> links = w.arm_link_poses();
  ASSERT_FALSE(links.empty());
  EXPECT_EQ(links.front().body, "arm_base");
  EXPECT_LT(links.front().pose.translation().norm(), 1e-12);
  EXPECT_THROW((void)w.object("unicorn"), Error);
}

TEST(World, SetObjectPoseRoundTripsAndStopsTheObject) {
  SceneDescription d = test::small_scene();
  PlacedObject box;
  box.type = "box";
  box.position = {0.6, 0.2};
  d.objects.push_back(box);
  World w = World::build(d, ObjectCatalogue::load_default());
  const ObjectId id = w.object("box").id;
  Pose p = Pose::Identity();
  p.translation() = Eigen::Vector3d(0.5, -0.1, 0.2);
  p.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  w.set_object_pose(id, p);
  EXPECT_LT((w.object_pose(id).matrix() - p.matrix()).norm(), 1e-12);
  EXPECT_EQ(w.object_velocity(id).norm(), 0.0);
  // Dropped from 20 cm it falls and comes to rest on the table.
  w.step(600);
  const Pose rest = w.object_pose(id);
  EXPECT_NEAR(rest.translation().z(), 0.05, 2e-3);
  EXPECT_TRUE(w.touching(w.geoms_of(id), 0)) << "resting on the table plane (world body)";
}

TEST(World, ArmPushesAnObjectAndTheContactIsSeen) {
  SceneDescription d = test::small_scene();
  PlacedObject box;
  box.type = "box";
  box.position = {0.36, 0.0};
  d.objects.push_back(box);
  World w = World::build(d, ObjectCatalogue::load_default());
  const ObjectId id = w.object("box").id;
  w.set_arm_configuration(low_pose(-0.6));
  ASSERT_FALSE(w.arm_touches(id));
  // Sweep j1 from -0.6 to 0.3 rad over 1.5 s: the pusher passes through the box's place.
  bool touched = false;
  const int steps = 750;
  for (int i = 0; i <= steps; ++i) {
    w.set_arm_targets(low_pose(-0.6 + 0.9 * i / steps));
    w.step();
    if (w.arm_touches(id)) {
      touched = true;
      EXPECT_EQ(w.objects_touched_by_arm(), std::vector<ObjectId>{id});
      EXPECT_TRUE(w.touching(w.geoms_of(kArmId),
                             mj_name2id(&w.model(), mjOBJ_BODY, w.object(id).body.c_str())));
    }
  }
  EXPECT_TRUE(touched);
  const Eigen::Vector3d moved = w.object_pose(id).translation() - w.object(id).initial_position;
  EXPECT_GT(moved.head<2>().norm(), 0.02) << "the push should move the box";
  EXPECT_GT(moved.y(), 0.0) << "j1 turns counter-clockwise: the box goes toward +y";
  EXPECT_TRUE(w.warnings().empty());
}

TEST(World, SameSceneSameMotionGivesIdenticalStates) {
  World a = all_objects_world();
  World b = all_objects_world();
  for (World* w : {&a, &b}) {
    w->set_arm_configuration(low_pose(-0.2));
    for (int i = 0; i < 300; ++i) {
      w->set_arm_targets(low_pose(-0.2 + 0.6 * i / 300.0));
      w->step();
    }
  }
  for (int i = 0; i < a.model().nq; ++i) ASSERT_EQ(a.data().qpos[i], b.data().qpos[i]) << i;
  a.reset();
  for (const SceneObject& o : a.objects()) {
    EXPECT_LT((a.object_pose(o.id).translation() - o.initial_position).norm(), 1e-8);
  }
  EXPECT_EQ(a.time(), 0.0);
}

TEST(World, AGraspIsAWeldThePhysicsCarriesAndReleases) {
  SceneDescription d = test::small_scene();
  PlacedObject box;
  box.type = "box";
  box.position = {0.5, 0.3};
  d.objects.push_back(box);
  d.grasp_object = "box";
  World w = World::build(d, ObjectCatalogue::load_default());
  const ObjectId id = w.object("box").id;
  const int link = mj_name2id(&w.model(), mjOBJ_BODY, kGraspArmBody);
  auto link_pose = [&] {
    for (const LinkPose& l : w.arm_link_poses())
      if (l.body == kGraspArmBody) return l.pose;
    ADD_FAILURE() << "no " << kGraspArmBody;
    return Pose::Identity();
  };
  ASSERT_GE(link, 0);
  // The pusher tip 15 cm above the table; the box hangs 1 cm under it, grasped there.
  robot::ArmState state(w.arm());
  const robot::JointVector q =
      robot::solve_ik(state, Eigen::Vector3d(0.25, 0.0, 0.15), w.arm_joints(), robot::IkOptions{})
          .q;
  w.set_arm_configuration(q);
  Pose p = Pose::Identity();
  p.translation() = w.ee_position() - Eigen::Vector3d(0, 0, 0.01 + 0.035);
  w.set_object_pose(id, p);
  EXPECT_FALSE(w.grasping());
  w.set_grasp(true, w.object("box").type.center());
  EXPECT_TRUE(w.grasping());
  const Pose held = link_pose().inverse() * w.object_pose(id);
  // The arm swings 0.6 rad about its base: the box goes with it, by physics alone.
  for (int i = 0; i < 400; ++i) {
    robot::JointVector qi = q;
    qi[0] += 0.6 * std::min(1.0, i / 300.0);
    w.set_arm_targets(qi);
    w.step();
  }
  const Pose now = link_pose().inverse() * w.object_pose(id);
  // A soft constraint: the 0.3 kg box sags by millimetres.
  EXPECT_LT((now.translation() - held.translation()).norm(), 0.008);
  EXPECT_LT(Eigen::AngleAxisd(now.linear().transpose() * held.linear()).angle(), 0.03);
  EXPECT_GT((w.object_pose(id).translation() - p.translation()).norm(), 0.1);
  // Turning it in the grip turns it about the anchor.
  w.set_grasp_rotation(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  w.step(200);
  const Pose turned = link_pose().inverse() * w.object_pose(id);
  EXPECT_NEAR(Eigen::AngleAxisd(held.linear().transpose() * turned.linear()).angle(), 0.3, 0.03);
  // Released, it falls.
  const double z_held = w.object_pose(id).translation().z();
  w.set_grasp(false);
  EXPECT_FALSE(w.grasping());
  w.step(400);
  EXPECT_LT(w.object_pose(id).translation().z(), z_held - 0.04);
}

// World.MujocoWarningsStopTheSimulation is in mujoco_messages_test.cpp: the programs here fail
// on any MuJoCo warning.

TEST(World, CameraPoseAndStereoPair) {
  SceneDescription d = test::small_scene();
  d.cameras[0].stereo_baseline = 0.12;
  World w = World::build(d, ObjectCatalogue{});
  ASSERT_EQ(w.camera_names(), (std::vector<std::string>{"camera_left", "camera_right"}));
  const geometry::Camera left = w.camera("camera_left");
  const geometry::Camera right = w.camera("camera_right");
  EXPECT_LT((left.center() - d.cameras[0].position).norm(), 1e-6);
  EXPECT_LT((left.R - right.R).norm(), 1e-9);
  // The right camera sits 12 cm along the left camera's x axis: t differs by (-0.12, 0, 0).
  EXPECT_LT((right.t - left.t - Eigen::Vector3d(-0.12, 0.0, 0.0)).norm(), 1e-6);
  // The target is on the optical axis: it projects to the principal point.
  const Eigen::Vector2d c = left.project(d.cameras[0].target);
  EXPECT_NEAR(c.x(), (320 - 1) / 2.0, 1e-6);
  EXPECT_NEAR(c.y(), (240 - 1) / 2.0, 1e-6);
  // World z up appears as image up (smaller v).
  EXPECT_LT(left.project(d.cameras[0].target + Eigen::Vector3d(0, 0, 0.05)).y(), c.y());
  EXPECT_NEAR(left.R.determinant(), 1.0, 1e-12);
  EXPECT_THROW((void)w.camera("camera"), Error);
}

TEST(World, VideoBackdropTextureIsWritten) {
  World w = World::build(test::small_scene(), ObjectCatalogue{});
  const cv::Mat img = test::quadrant_image(64, 36);
  w.set_texture_image(kBackdropTexture, img);
  const int id = w.texture_id(kBackdropTexture);
  const unsigned char* texel = w.model().tex_rgb + w.model().tex_adr[id];
  EXPECT_EQ(texel[0], 255);  // RGB order: the top-left quadrant is red
  EXPECT_EQ(texel[2], 0);
  EXPECT_THROW(w.set_texture_image("no_such_texture", img), Error);
  EXPECT_THROW(w.set_texture_image(kBackdropTexture, cv::Mat()), Error);
}

}  // namespace
}  // namespace proprio::sim
