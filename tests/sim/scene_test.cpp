// Object catalogue, scene description and scene building: no rendering here.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "proprio/core/error.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_builder.hpp"
#include "proprio/sim/scene_description.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {

namespace fs = std::filesystem;
using test::temp_dir;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

fs::path write_text(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p) << text;
  return p;
}

TEST(ObjectCatalogue, DefaultHoldsTheThesisObjectsWithReadablePhotographs) {
  const ObjectCatalogue c = ObjectCatalogue::load_default();
  for (const char* name : {"book", "mug", "bottle", "spirit-level", "rabbit", "cd", "calculator",
                           "giraffe", "bike", "box"}) {
    ASSERT_TRUE(c.contains(name)) << name;
    const ObjectType& t = c.get(name);
    EXPECT_TRUE(t.texture.is_absolute()) << name;
    EXPECT_FALSE(read_image(t.texture).empty()) << name;
    EXPECT_GT(t.bottom(), -1e-9) << name << ": the origin is below the object's lowest point";
    EXPECT_LT(t.bottom(), 0.2) << name;
  }
  // Distinct photographs, so that objects look distinct.
  std::set<fs::path> photos;
  for (const ObjectType& t : c.types()) photos.insert(t.texture);
  EXPECT_EQ(photos.size(), c.types().size());
}

TEST(ObjectCatalogue, UnknownObjectNamesTheObjectAndTheKnownOnes) {
  const ObjectCatalogue c = ObjectCatalogue::load_default();
  const std::string message = error_of([&] { (void)c.get("unicorn"); });
  EXPECT_NE(message.find("unknown object 'unicorn'"), std::string::npos) << message;
  EXPECT_NE(message.find("giraffe"), std::string::npos) << message;
}

TEST(ObjectCatalogue, ObjectGeometryKnownAnswers) {
  ObjectType t;
  t.name = "mug";
  t.texture = "x.png";
  ObjectPart body;
  body.shape = PartShape::kCylinder;
  body.size = {0.04, 0.05, 0.0};
  ObjectPart handle;
  handle.shape = PartShape::kBox;
  handle.size = {0.01, 0.005, 0.03};
  handle.position = {0.05, 0.0, 0.0};
  t.parts = {body, handle};
  EXPECT_NEAR(t.bottom(), 0.05, 1e-12);
  // The handle box corner (0.06, 0.005) is the farthest point of the parts' bounding boxes.
  EXPECT_NEAR(t.footprint_radius(), std::hypot(0.06, 0.005), 1e-12);
  EXPECT_LT((t.half_extents() - Eigen::Vector3d(0.05, 0.04, 0.05)).norm(), 1e-12);
  EXPECT_LT((t.center() - Eigen::Vector3d(0.01, 0.0, 0.0)).norm(), 1e-12);
  // A capsule lying along x (turned by pi/2 about y) is as low as its radius.
  ObjectPart lying;
  lying.shape = PartShape::kCapsule;
  lying.size = {0.01, 0.05, 0.0};
  lying.euler = {0.0, std::numbers::pi / 2, 0.0};
  t.parts = {lying};
  EXPECT_NEAR(t.bottom(), 0.01, 1e-9);
  EXPECT_NEAR(t.half_extents().x(), 0.06, 1e-9);
}

TEST(ObjectCatalogue, BadFilesAreReportedWithFileAndObject) {
  const std::string head = R"({"format": "proprio.object_catalogue", "version": 1, "objects": [)";
  struct Case {
    std::string body;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {R"({"name": "a", "texture": "baboon.jpg", "mass": 1, "friction": 1, "shape": "cone",
           "size": [1]})",
       "unknown shape 'cone'"},
      {R"({"name": "a", "texture": "baboon.jpg", "mass": 1, "friction": 1, "shape": "box",
           "size": [0.1, 0.1]})",
       "box needs 3 positive size entries"},
      {R"({"name": "a", "texture": "baboon.jpg", "mass": -1, "friction": 1, "shape": "sphere",
           "size": [0.1]})",
       "mass must be in"},
      {R"({"name": "a", "texture": "no_such_photo.jpg", "mass": 1, "friction": 1,
           "shape": "sphere", "size": [0.1]})",
       "texture 'no_such_photo.jpg' not found"},
      {R"({"name": "a", "texture": "baboon.jpg", "mass": 1, "friction": 1, "shape": "sphere",
           "size": [NaN]})",
       ""},  // not JSON: the parser's message, with the line
      {R"({"name": "a b", "texture": "baboon.jpg", "mass": 1, "friction": 1, "shape": "sphere",
           "size": [0.1]})",
       "names may hold only"},
      {R"({"name": "a", "mass": 1, "friction": 1, "shape": "sphere", "size": [0.1]})",
       "missing key 'texture'"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path file =
        write_text("bad_catalogue_" + std::to_string(i) + ".json", head + cases[i].body + "]}");
    const std::string message = error_of([&] { (void)ObjectCatalogue::load(file); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].expect), std::string::npos) << message;
  }
  const fs::path dup = write_text(
      "dup_catalogue.json",
      head +
          R"({"name": "a", "texture": "baboon.jpg", "mass": 1, "friction": 1, "shape": "sphere",
              "size": [0.1]}, {"name": "a", "texture": "baboon.jpg", "mass": 1, "friction": 1,
              "shape": "sphere", "size": [0.1]}]})");
  EXPECT_NE(error_of([&] { (void)ObjectCatalogue::load(dup); }).find("defined twice"),
            std::string::npos);
}

TEST(ObjectCatalogue, UserObjectsUseTheSameFields) {
  const core::Json j = core::Json::parse(
      R"({"name": "puck", "texture": "orange.jpg", "mass": 0.1, "friction": 0.3,
          "shape": "cylinder", "size": [0.05, 0.01]})");
  const ObjectType t = parse_object_type(j, "user", {ObjectCatalogue::default_texture_dir()});
  EXPECT_EQ(t.parts.size(), 1U);
  EXPECT_EQ(t.parts[0].shape, PartShape::kCylinder);
  EXPECT_NEAR(t.bottom(), 0.01, 1e-12);
  ObjectCatalogue c = ObjectCatalogue::load_default();
  c.add(t);
  EXPECT_TRUE(c.contains("puck"));
  EXPECT_THROW(c.add(t), Error);
}

TEST(SceneBuilder, UnknownObjectInTheSceneIsAnError) {
  SceneDescription d = test::small_scene();
  PlacedObject o;
  o.type = "unicorn";
  d.objects.push_back(o);
  const std::string message =
      error_of([&] { (void)build_scene(d, ObjectCatalogue::load_default()); });
  EXPECT_NE(message.find("unknown object 'unicorn'"), std::string::npos) << message;
}

TEST(SceneBuilder, UnreadableTextureNamesTheFile) {
  const fs::path fake = write_text("not_an_image.png", "this is text, not a PNG");
  ObjectType t;
  t.name = "fake";
  t.texture = fake;
  ObjectPart p;
  p.size = {0.05, 0.05, 0.05};
  t.parts = {p};
  SceneDescription d = test::small_scene();
  PlacedObject o;
  o.custom = t;
  d.objects.push_back(o);
  std::string message = error_of([&] { (void)build_scene(d, ObjectCatalogue{}); });
  EXPECT_NE(message.find(fake.string()), std::string::npos) << message;
  EXPECT_NE(message.find("not an image proprio reads"), std::string::npos) << message;

  d.objects.clear();
  d.backdrop.image = temp_dir() / "missing_backdrop.jpg";
  message = error_of([&] { (void)build_scene(d, ObjectCatalogue{}); });
  EXPECT_NE(message.find("missing_backdrop.jpg: no such file"), std::string::npos) << message;
}

TEST(SceneBuilder, InstanceNamesAreUniqueAndIdsFollowTheDescription) {
  SceneDescription d = test::small_scene();
  for (double x : {0.3, 0.5, 0.7}) {
    PlacedObject o;
    o.type = "mug";
    o.position = {x, 0.0};
    d.objects.push_back(o);
  }
  PlacedObject named;
  named.type = "box";
  named.name = "crate";
  d.objects.push_back(named);
  const SceneModel s = build_scene(d, ObjectCatalogue::load_default());
  ASSERT_EQ(s.objects.size(), 4U);
  EXPECT_EQ(s.objects[0].name, "mug_1");
  EXPECT_EQ(s.objects[2].name, "mug_3");
  EXPECT_EQ(s.objects[3].name, "crate");
  for (std::size_t i = 0; i < s.objects.size(); ++i) EXPECT_EQ(s.objects[i].id, i + 1);
  // Resting on the table: the mug's origin is half its height up.
  EXPECT_NEAR(s.objects[0].initial_position.z(), 0.05, 1e-12);
  EXPECT_NE(s.xml.find("arm.xml"), std::string::npos);

  named.name = "mug_1";
  d.objects.push_back(named);
  EXPECT_NE(error_of([&] {
              (void)build_scene(d, ObjectCatalogue::load_default());
            }).find("two objects are called 'mug_1'"),
            std::string::npos);
}

TEST(SceneDescription, ValidationRejectsAbsurdInput) {
  const auto message_for = [](const std::function<void(SceneDescription&)>& change) {
    SceneDescription d = test::small_scene();
    change(d);
    return error_of([&] { d.validate(); });
  };
  EXPECT_NE(message_for([](SceneDescription& d) { d.cameras.clear(); }).find("no camera"),
            std::string::npos);
  EXPECT_NE(
      message_for([](SceneDescription& d) { d.cameras[0].width = 100000; }).find("image size"),
      std::string::npos);
  EXPECT_NE(message_for([](SceneDescription& d) {
              d.cameras[0].target = d.cameras[0].position;
            }).find("target equals its position"),
            std::string::npos);
  EXPECT_NE(message_for([](SceneDescription& d) { d.timestep = std::nan(""); }).find("timestep"),
            std::string::npos);
  EXPECT_NE(message_for([](SceneDescription& d) {
              PlacedObject o;
              o.type = "mug";
              o.position = {std::nan(""), 0.0};
              d.objects.push_back(o);
            }).find("not finite"),
            std::string::npos);
  EXPECT_NE(message_for([](SceneDescription& d) {
              d.arm_model = "/no/such/arm.xml";
            }).find("/no/such/arm.xml: no such arm model file"),
            std::string::npos);
  EXPECT_NE(message_for([](SceneDescription& d) {
              d.cameras.push_back(d.cameras[0]);
            }).find("two cameras are called 'camera'"),
            std::string::npos);
  EXPECT_EQ(message_for([](SceneDescription&) {}), "no error");
}

TEST(SceneBuilder, CubeTextureCropsEachFaceToItsAspect) {
  // A 4:1 photograph on a flat box: the top face (x by y = 4:1) keeps the whole photograph, the
  // end faces (y by z = 1:1) get its centre square.
  cv::Mat photo(100, 400, CV_8UC3, cv::Scalar(0, 0, 0));
  photo(cv::Rect(150, 0, 100, 100)).setTo(cv::Scalar(255, 255, 255));  // the centre square
  const cv::Mat cube = cube_texture(photo, {0.2, 0.05, 0.05}, 64);
  ASSERT_EQ(cube.rows, 6 * 64);
  ASSERT_EQ(cube.cols, 64);
  const auto face_mean = [&](int k) { return cv::mean(cube.rowRange(64 * k, 64 * (k + 1)))[0]; };
  EXPECT_GT(face_mean(0), 250.0);             // +x end: all white
  EXPECT_GT(face_mean(1), 250.0);             // -x end
  EXPECT_NEAR(face_mean(4), 255.0 / 4, 8.0);  // +z top: the whole strip, a quarter white
}

}  // namespace
}  // namespace proprio::sim
