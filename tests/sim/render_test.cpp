// Renderer: colour images, id masks and depth agree with each other, with the camera model and
// with the world's ground truth; textures show the right way up; rendering is deterministic.
#include "proprio/sim/renderer.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {

robot::JointVector low_pose(double yaw) {
  robot::JointVector q;
  q << yaw, 0.4, -0.8, -0.9, 0.0;
  return q;
}

cv::Point pixel(const Eigen::Vector2d& x) {
  return {static_cast<int>(std::lround(x.x())), static_cast<int>(std::lround(x.y()))};
}

bool inside(const cv::Mat& image, const cv::Point& p) {
  return p.x >= 0 && p.y >= 0 && p.x < image.cols && p.y < image.rows;
}

// The ten catalogue objects and the arm, at 320x240, one renderer for the whole suite (making a
// GL context and uploading the textures takes a while in software).
class RenderedScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SceneDescription d = test::small_scene();
    test::add_all_objects(d);
    // A user object: a plain ball, whose silhouette centre is where its centre projects.
    ObjectType ball;
    ball.name = "ball";
    ball.texture = ObjectCatalogue::default_texture_dir() / "orange.jpg";
    ball.parts = {ObjectPart{PartShape::kSphere, {0.025, 0.0, 0.0}, {0, 0, 0}, {0, 0, 0}}};
    PlacedObject o;
    o.custom = ball;
    o.position = {0.34, 0.16};
    d.objects.push_back(o);
    d.cameras[0].stereo_baseline = 0.1;
    world_ = std::make_unique<World>(World::build(d, ObjectCatalogue::load_default()));
    // Pointing toward the camera, out of the way of the objects, marker in view.
    world_->set_arm_configuration(low_pose(-1.3));
    RenderOptions options;
    options.shadows = false;  // so that moving an object changes only its own pixels
    options.reflections = false;
    renderer_ = std::make_unique<Renderer>(*world_, options);
  }
  static void TearDownTestSuite() {
    renderer_.reset();
    world_.reset();
  }
  static std::unique_ptr<World> world_;
  static std::unique_ptr<Renderer> renderer_;
};
std::unique_ptr<World> RenderedScene::world_;
std::unique_ptr<Renderer> RenderedScene::renderer_;

TEST_F(RenderedScene, ImagesHaveTheCameraSizeAndTypes) {
  const Frame f = renderer_->render(*world_, "camera_left", kPassRgb | kPassMask | kPassDepth);
  EXPECT_EQ(f.rgb.size(), cv::Size(320, 240));
  EXPECT_EQ(f.rgb.type(), CV_8UC3);
  EXPECT_EQ(f.mask.type(), CV_16UC1);
  EXPECT_EQ(f.depth.type(), CV_32FC1);
  EXPECT_THROW((void)renderer_->rgb(*world_, "no_such_camera"), Error);
}

TEST_F(RenderedScene, EveryObjectAndTheArmAppearInTheMask) {
  for (const std::string& camera : world_->camera_names()) {
    const cv::Mat mask = renderer_->mask(*world_, camera);
    std::map<int, int> count;
    for (auto it = mask.begin<std::uint16_t>(); it != mask.end<std::uint16_t>(); ++it) ++count[*it];
    for (const SceneObject& o : world_->objects()) {
      EXPECT_GT(count[o.id], 30) << o.name << " in " << camera;
    }
    EXPECT_GT(count[kArmId], 500) << camera;
    EXPECT_GT(count[kBackgroundId], mask.total() / 3) << camera;
    EXPECT_EQ(count.size(), world_->objects().size() + 2) << "ids other than objects, arm, 0";
  }
}

TEST_F(RenderedScene, MaskIsExactlyWhereTheObjectIsDrawn) {
  // Take each object away: the pixels that change are the ones its id covers.
  const std::string camera = "camera_left";
  const cv::Mat mask = renderer_->mask(*world_, camera);
  const cv::Mat with = renderer_->rgb(*world_, camera);
  for (const SceneObject& o : world_->objects()) {
    const Pose pose = world_->object_pose(o.id);
    Pose away = pose;
    away.translation() = Eigen::Vector3d(0.0, 0.0, -5.0);  // under the floor
    world_->set_object_pose(o.id, away);
    const cv::Mat without = renderer_->rgb(*world_, camera);
    world_->set_object_pose(o.id, pose);
    cv::Mat diff;
    cv::absdiff(with, without, diff);
    cv::Mat changed;
    cv::cvtColor(diff, changed, cv::COLOR_BGR2GRAY);
    changed = changed > 0;
    const cv::Mat own = mask == o.id;
    const double both = cv::countNonZero(changed & own);
    const double either = cv::countNonZero(changed | own);
    EXPECT_GT(both / either, 0.995) << o.name << ": changed " << cv::countNonZero(changed)
                                   << " px, mask " << cv::countNonZero(own) << " px";
  }
  EXPECT_EQ(cv::norm(renderer_->rgb(*world_, camera), with, cv::NORM_INF), 0.0);
}

TEST_F(RenderedScene, CameraProjectsEachObjectOntoItsMask) {
  for (const std::string& camera : world_->camera_names()) {
    const geometry::Camera cam = world_->camera(camera);
    const cv::Mat mask = renderer_->mask(*world_, camera);
    for (const SceneObject& o : world_->objects()) {
      const Pose pose = world_->object_pose(o.id);
      // The centre of the object's main (first) part lies on the object.
      const cv::Point p = pixel(cam.project(pose * o.type.parts.front().position));
      ASSERT_TRUE(inside(mask, p)) << o.name;
      EXPECT_EQ(mask.at<std::uint16_t>(p), o.id) << o.name << " in " << camera;
      // The centre of its bounding box lands near the centroid of its pixels.
      const cv::Moments m = cv::moments(mask == o.id, true);
      const Eigen::Vector2d centroid(m.m10 / m.m00, m.m01 / m.m00);
      const double radius = std::sqrt(m.m00 / CV_PI);
      EXPECT_LT((cam.project(pose * o.type.center()) - centroid).norm(), 0.5 * radius)
          << o.name << " in " << camera;
    }
  }
}

TEST_F(RenderedScene, BallSilhouetteIsCentredOnItsProjectionToASubpixel) {
  // A principal point half a pixel off, or an image flipped by one row, shows here.
  const SceneObject& ball = world_->object("ball");
  const Eigen::Vector3d centre = world_->object_pose(ball.id).translation();
  for (const std::string& camera : world_->camera_names()) {
    const geometry::Camera cam = world_->camera(camera);
    const Frame f = renderer_->render(*world_, camera, kPassMask | kPassDepth);
    const cv::Moments m = cv::moments(f.mask == ball.id, true);
    ASSERT_GT(m.m00, 50) << camera;
    const Eigen::Vector2d centroid(m.m10 / m.m00, m.m01 / m.m00);
    EXPECT_LT((centroid - cam.project(centre)).norm(), 0.2) << camera;
    // Its area is that of the projected disc (radius f r / depth), to a few percent.
    const double r_px = cam.K(0, 0) * 0.025 / cam.depth(centre);
    EXPECT_NEAR(m.m00 / (CV_PI * r_px * r_px), 1.0, 0.06) << camera;
    EXPECT_NEAR(f.depth.at<float>(pixel(cam.project(centre))), cam.depth(centre) - 0.025, 2e-3);
  }
}

TEST_F(RenderedScene, MarkerProjectionHitsTheMarkerToASubpixel) {
  // The calibration marker (a magenta sphere on the end-effector) seen in the colour image is
  // where the camera model puts its centre.
  const int marker = mj_name2id(&world_->model(), mjOBJ_GEOM, "marker");
  ASSERT_GE(marker, 0);
  const Eigen::Vector3d centre =
      Eigen::Map<const Eigen::Vector3d>(world_->data().geom_xpos + 3 * marker);
  for (const std::string& camera : world_->camera_names()) {
    const geometry::Camera cam = world_->camera(camera);
    const Frame f = renderer_->render(*world_, camera, kPassRgb | kPassMask | kPassDepth);
    const Eigen::Vector2d x = cam.project(centre);
    ASSERT_TRUE(inside(f.mask, pixel(x)));
    EXPECT_EQ(f.mask.at<std::uint16_t>(pixel(x)), kArmId);
    cv::Mat magenta;
    cv::inRange(f.rgb, cv::Scalar(120, 0, 120), cv::Scalar(255, 90, 255), magenta);
    magenta &= (f.mask == kArmId);
    const cv::Moments m = cv::moments(magenta, true);
    ASSERT_GT(m.m00, 20) << camera;
    const Eigen::Vector2d centroid(m.m10 / m.m00, m.m01 / m.m00);
    // Shading makes the thresholded blob a little lopsided.
    EXPECT_LT((centroid - x).norm(), 1.0) << camera;
    // Depth at the centre pixel: the sphere's front surface, one radius nearer than its centre.
    const double radius = world_->model().geom_size[3 * marker];
    EXPECT_NEAR(f.depth.at<float>(pixel(x)), cam.depth(centre) - radius, 2e-3) << camera;
  }
}

TEST_F(RenderedScene, DepthBackProjectsOntoTheTableTop) {
  const std::string camera = "camera_left";
  const geometry::Camera cam = world_->camera(camera);
  const Frame f = renderer_->render(*world_, camera, kPassMask | kPassDepth);
  const TableSpec& table = world_->scene().description.table;
  const Eigen::Matrix3d K_inv = cam.K.inverse();
  int checked = 0;
  for (int v = 0; v < f.depth.rows; v += 7) {
    for (int u = 0; u < f.depth.cols; u += 7) {
      const double z = f.depth.at<float>(v, u);
      if (f.mask.at<std::uint16_t>(v, u) != kBackgroundId || z <= 0.0) continue;
      const Eigen::Vector3d X = cam.R.transpose() * (z * K_inv * Eigen::Vector3d(u, v, 1) - cam.t);
      const Eigen::Vector2d off = (X.head<2>() - table.center).cwiseAbs();
      if ((off - table.size / 2).maxCoeff() > -0.02 || std::abs(X.z()) > 0.05) continue;
      EXPECT_NEAR(X.z(), 0.0, 1.5e-3) << "pixel " << u << "," << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(Renderer, TexturesAreUprightAndUnmirroredOnEveryFaceAndTheBackdrop) {
  const cv::Mat quadrants = test::quadrant_image();
  const std::filesystem::path photo = test::temp_dir() / "quadrants.png";
  cv::imwrite(photo.string(), quadrants);
  SceneDescription d = test::small_scene();
  d.arm_model.clear();
  ObjectType t;
  t.name = "quadrant_box";
  t.texture = photo;
  ObjectPart part;
  part.size = {0.12, 0.08, 0.06};
  t.parts = {part};
  PlacedObject o;
  o.custom = t;
  o.position = {0.4, 0.0};
  d.objects = {o};
  const Eigen::Vector3d c(0.4, 0.0, 0.06);  // box centre
  struct View {
    std::string name;
    Eigen::Vector3d position;
    Eigen::Vector3d up;
    Eigen::Vector3d right;  // seen from the camera, on the face
    Eigen::Vector3d face_up;
    Eigen::Vector3d face_centre;
  };
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d Y = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d Z = Eigen::Vector3d::UnitZ();
  const std::vector<View> views = {
      {"front", c + Eigen::Vector3d(0, -0.6, 0.2), Z, X, Z, c - 0.08 * Y},
      {"back", c + Eigen::Vector3d(0, 0.6, 0.2), Z, -X, Z, c + 0.08 * Y},
      {"right", c + Eigen::Vector3d(0.6, 0, 0.2), Z, Y, Z, c + 0.12 * X},
      {"left", c + Eigen::Vector3d(-0.6, 0, 0.2), Z, -Y, Z, c - 0.12 * X},
      {"top", c + Eigen::Vector3d(0, 0, 0.7), Y, X, Y, c + 0.06 * Z},
  };
  d.cameras.clear();
  for (const View& v : views) {
    CameraSpec cam;
    cam.name = v.name;
    cam.width = 320;
    cam.height = 240;
    cam.position = v.position;
    cam.target = c;
    cam.up = v.up;
    d.cameras.push_back(cam);
  }
  CameraSpec wall;  // facing the backdrop
  wall.name = "wall";
  wall.width = 320;
  wall.height = 240;
  wall.position = d.backdrop.center - Eigen::Vector3d(0, 1.6, 0);
  wall.target = d.backdrop.center;
  d.cameras.push_back(wall);
  World w = World::build(d, ObjectCatalogue{});
  RenderOptions options;
  options.shadows = false;
  Renderer r(w, options);

  const auto expect_quadrants = [](const cv::Mat& rgb, const geometry::Camera& cam,
                                   const Eigen::Vector3d& centre, const Eigen::Vector3d& right,
                                   const Eigen::Vector3d& up, const std::string& what) {
    const std::map<char, std::pair<double, double>> corners = {
        {'r', {-1, 1}}, {'g', {1, 1}}, {'b', {-1, -1}}, {'y', {1, -1}}};
    for (const auto& [colour, s] : corners) {
      const cv::Point p = pixel(cam.project(centre + s.first * right + s.second * up));
      ASSERT_TRUE(inside(rgb, p)) << what;
      EXPECT_EQ(test::colour_class(rgb.at<cv::Vec3b>(p)), colour)
          << what << " at " << p << ": " << rgb.at<cv::Vec3b>(p);
    }
  };
  const Eigen::Vector3d half(0.12, 0.08, 0.06);
  for (const View& v : views) {
    const cv::Mat rgb = r.rgb(w, v.name);
    // Quadrant centres: half way from the face centre to its edges.
    const double half_w = 0.5 * std::abs(v.right.dot(half));
    const double half_h = 0.5 * std::abs(v.face_up.dot(half));
    expect_quadrants(rgb, w.camera(v.name), v.face_centre, half_w * v.right, half_h * v.face_up,
                     v.name + " face");
  }
  // The backdrop: a "video frame" written into its texture and uploaded.
  w.set_texture_image(kBackdropTexture, quadrants);
  r.upload_texture(w, kBackdropTexture);
  const BackdropSpec& b = d.backdrop;
  expect_quadrants(r.rgb(w, "wall"), w.camera("wall"), b.center, 0.25 * b.size.x() * X,
                   0.25 * b.size.y() * Z, "backdrop");
}

TEST(Renderer, SameSceneRendersIdenticalImages) {
  std::vector<Frame> frames;
  for (int run = 0; run < 2; ++run) {
    SceneDescription d = test::small_scene();
    test::add_all_objects(d);
    World w = World::build(d, ObjectCatalogue::load_default());
    w.set_arm_configuration(low_pose(-0.2));
    for (int i = 0; i < 100; ++i) {
      w.set_arm_targets(low_pose(-0.2 + 0.3 * i / 100.0));
      w.step();
    }
    Renderer r(w);  // shadows and reflections on
    frames.push_back(r.render(w, "camera", kPassRgb | kPassMask | kPassDepth));
  }
  EXPECT_EQ(cv::norm(frames[0].rgb, frames[1].rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(frames[0].mask, frames[1].mask, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(frames[0].depth, frames[1].depth, cv::NORM_INF), 0.0);
}

TEST(GlContext, BackendsByNameAndOsMesaWorks) {
  EXPECT_EQ(parse_gl_backend("osmesa"), GlBackend::kOsMesa);
  EXPECT_EQ(parse_gl_backend("egl"), GlBackend::kEgl);
  EXPECT_EQ(to_string(GlBackend::kAuto), "auto");
  try {
    (void)parse_gl_backend("vulkan");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'vulkan'"), std::string::npos);
  }
  const GlContext context = GlContext::create(GlBackend::kOsMesa);
  EXPECT_EQ(context.backend(), GlBackend::kOsMesa);
  EXPECT_FALSE(context.renderer_name().empty());
}

}  // namespace
}  // namespace proprio::sim
