// proprio._proprio.sim: the simulated world (a scene built from a description, stepped and
// rendered to arrays) and the simulated robot behind the robot interface (look, push).
//
// Threads: a Scene or SimulatedRobot owns a GL context and MuJoCo state; use each from one
// thread. Long calls (push, step) release the GIL and are serialised by the object's own mutex.
#include <memory>
#include <mutex>

#include "common.hpp"
#include "options.hpp"
#include "proprio/robot/robot_interface.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/scene_description.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::python {

namespace {

robot::JointVector joints_from(const py::handle& obj, const char* name) {
  const auto a = require_array<double>(obj, name, 1, {robot::kArmJoints});
  robot::JointVector q;
  for (int i = 0; i < robot::kArmJoints; ++i) {
    if (!std::isfinite(a.at(i)))
      throw py::value_error(std::string(name) + ": expected finite angles");
    q(i) = a.at(i);
  }
  return q;
}

py::array_t<double> joints_array(const robot::JointVector& q) {
  return array_from_vector(Eigen::VectorXd(q));
}

// Two numbers (x, y) from any sequence or array of reals (converted: a point is not bulk data).
Eigen::Vector2d point2(const py::handle& obj, const char* name) {
  py::array_t<double> a;
  try {
    a = py::array_t<double, py::array::forcecast>::ensure(obj);
  } catch (const py::error_already_set&) {
  }
  if (!a || a.ndim() != 1 || a.shape(0) != 2) {
    throw py::value_error(std::string(name) + ": expected 2 numbers (x, y), got " +
                          std::string(py::repr(obj)));
  }
  const Eigen::Vector2d p(a.at(0), a.at(1));
  if (!p.allFinite()) throw py::value_error(std::string(name) + ": expected finite numbers");
  return p;
}

// A world and its renderer, kept together (the renderer serves the world it was made with).
struct Scene {
  std::unique_ptr<sim::World> world;
  std::unique_ptr<sim::Renderer> renderer;
  std::mutex mutex;
};

sim::World& live(const Scene& s) {
  if (!s.world) throw py::value_error("the scene is closed");
  return *s.world;
}

std::shared_ptr<Scene> make_scene(const py::list& objects, int width, int height, bool shadows,
                                  bool arm) {
  auto description = sim::default_scene();
  if (!arm) description.arm_model.clear();
  for (auto& c : description.cameras) {
    c.width = width;
    c.height = height;
  }
  for (const auto& item : objects) {
    const auto t = py::cast<py::tuple>(item);
    if (t.size() < 3 || t.size() > 4) {
      throw py::value_error("objects: expected (type, x, y[, yaw]) tuples");
    }
    sim::PlacedObject o;
    o.type = py::cast<std::string>(t[0]);
    o.position = {py::cast<double>(t[1]), py::cast<double>(t[2])};
    if (t.size() == 4) o.yaw = py::cast<double>(t[3]);
    description.objects.push_back(o);
  }
  auto scene = std::make_shared<Scene>();
  {
    py::gil_scoped_release release;
    const auto catalogue = sim::ObjectCatalogue::load_default();
    scene->world = std::make_unique<sim::World>(sim::World::build(description, catalogue));
    sim::RenderOptions ro;
    ro.shadows = shadows;
    scene->renderer = std::make_unique<sim::Renderer>(*scene->world, ro);
  }
  return scene;
}

py::dict render_frame(Scene& s, const std::string& camera, bool mask, bool depth) {
  unsigned passes = sim::kPassRgb;
  if (mask) passes |= sim::kPassMask;
  if (depth) passes |= sim::kPassDepth;
  const std::lock_guard lock(s.mutex);
  auto& world = live(s);
  const auto f = s.renderer->render(world, camera, passes);
  py::dict d;
  d["rgb"] = array_from_image(f.rgb);
  d["mask"] = mask ? py::object(array_from_image(f.mask, false)) : py::none();
  d["depth"] = depth ? py::object(array_from_image(f.depth, false)) : py::none();
  return d;
}

py::dict look_dict(const robot::Look& look) {
  py::dict d;
  d["image"] = array_from_image(look.image);
  d["t"] = look.t;
  d["q"] = joints_array(look.q);
  d["ee"] = array_from_vector(Eigen::VectorXd(look.ee));
  d["camera"] = look.camera;
  d["arm_mask"] =
      look.arm_mask.empty() ? py::none() : py::object(array_from_image(look.arm_mask, false));
  return d;
}

py::dict report_dict(const robot::PushReport& r) {
  py::dict d;
  d["start"] = array_from_vector(Eigen::VectorXd(r.push.start));
  d["end"] = array_from_vector(Eigen::VectorXd(r.push.end));
  d["episode_dir"] =
      r.episode_dir.empty() ? py::none() : py::object(py::str(r.episode_dir.string()));
  d["frames"] = r.frames;
  d["touched"] = r.touched;
  d["first_touch_frame"] = r.first_touch_frame ? py::cast(*r.first_touch_frame) : py::none();
  d["seconds"] = r.seconds;
  d["message"] = r.message;
  return d;
}

struct Robot {
  std::unique_ptr<sim::SimulatedRobot> robot;
  std::mutex mutex;
};

sim::SimulatedRobot& live(const Robot& r) {
  if (!r.robot) throw py::value_error("the robot is closed");
  return *r.robot;
}

robot::PushRecording recording(const py::object& episode_dir, double fps, bool overwrite) {
  robot::PushRecording rec;
  if (!episode_dir.is_none()) rec.episode_dir = to_path(episode_dir, "episode_dir");
  rec.fps = fps;
  rec.overwrite = overwrite;
  rec.run = python_provenance(std::nullopt);
  return rec;
}

}  // namespace

void bind_sim(py::module_& m) {
  m.def(
      "catalogue_names", []() { return sim::ObjectCatalogue::load_default().names(); },
      "The names of the catalogue's objects (data/objects/catalogue.json).");

  py::class_<Scene, std::shared_ptr<Scene>>(
      m, "Scene",
      "A MuJoCo world built from the default scene (table, backdrop, one camera called 'camera', "
      "lights, the arm) with catalogue objects placed on the table, and its headless renderer.")
      .def(py::init(&make_scene), py::arg("objects") = py::list(), py::arg("width") = 640,
           py::arg("height") = 480, py::arg("shadows") = false, py::arg("arm") = true,
           "objects: (catalogue type, x, y[, yaw]) tuples, world metres and radians.")
      .def(
          "step",
          [](Scene& s, int steps) {
            if (steps < 0) throw py::value_error("steps: expected >= 0");
            py::gil_scoped_release release;
            const std::lock_guard lock(s.mutex);
            live(s).step(steps);
          },
          py::arg("steps") = 1, "Advances the physics by `steps` time steps (GIL released).")
      .def(
          "reset", [](Scene& s) { live(s).reset(); }, "Back to the initial state.")
      .def(
          "close",
          [](Scene& s) {
            const std::lock_guard lock(s.mutex);
            s.renderer.reset();
            s.world.reset();
          },
          "Frees the GL context and the MuJoCo state now (also done at exit); the scene is "
          "unusable after it.")
      .def_property_readonly("time", [](const Scene& s) { return live(s).time(); })
      .def_property_readonly("timestep", [](const Scene& s) { return live(s).timestep(); })
      .def_property_readonly("camera_names", [](const Scene& s) { return live(s).camera_names(); })
      .def_property_readonly(
          "object_names",
          [](const Scene& s) {
            std::vector<std::string> names;
            for (const auto& o : live(s).objects()) names.push_back(o.name);
            return names;
          },
          "Instance names; object i+1 has id i+1 in the masks.")
      .def(
          "render",
          [](Scene& s, const std::string& camera, bool mask, bool depth) {
            return render_frame(s, camera, mask, depth);
          },
          py::arg("camera") = "camera", py::arg("mask") = true, py::arg("depth") = false,
          "Renders a camera: dict of rgb (H x W x 3 uint8 RGB), mask (H x W uint16 object ids, 0 "
          "background, 65535 the arm) and depth (H x W float32 metres, 0 = nothing), each a new "
          "array (copied from the GL buffers).")
      .def(
          "camera", [](const Scene& s, const std::string& name) { return live(s).camera(name); },
          py::arg("name") = "camera", "The camera as a pinhole model (K, R, t) in its pose.")
      .def(
          "object_pose",
          [](const Scene& s, const std::string& name) {
            const auto pose = live(s).object_pose(live(s).object(name).id);
            return array_from_matrix(pose.matrix());
          },
          py::arg("name"), "4 x 4 world-from-object transform, metres.")
      .def_property_readonly("has_arm", [](const Scene& s) { return live(s).has_arm(); })
      .def_property_readonly(
          "arm_joints",
          [](const Scene& s) {
            if (!live(s).has_arm()) throw py::value_error("the scene has no arm");
            return joints_array(live(s).arm_joints());
          },
          "The arm's joint angles j1..j5, rad.")
      .def(
          "set_arm_configuration",
          [](Scene& s, const py::handle& q) {
            if (!live(s).has_arm()) throw py::value_error("the scene has no arm");
            live(s).set_arm_configuration(joints_from(q, "q"));
          },
          py::arg("q"), "Puts the arm at q (5 angles, rad) at once.")
      .def(
          "set_arm_targets",
          [](Scene& s, const py::handle& q) {
            if (!live(s).has_arm()) throw py::value_error("the scene has no arm");
            live(s).set_arm_targets(joints_from(q, "q"));
          },
          py::arg("q"), "Position-actuator targets (5 angles, rad); step() moves the arm there.")
      .def_property_readonly(
          "ee_position",
          [](const Scene& s) { return array_from_vector(Eigen::VectorXd(live(s).ee_position())); },
          "End-effector position, world, metres.");

  bind_options<sim::TableOptions>(
      m, "TableOptions", "The table a SimulatedRobot starts with (`proprio push`'s flags).");

  py::class_<Robot, std::shared_ptr<Robot>>(
      m, "SimulatedRobot",
      "The robot interface (robot::Robot: look, push) on one persistent simulated table of "
      "catalogue objects; the ground truth is kept aside for scoring.")
      .def(py::init([](const sim::TableOptions& options, const std::vector<std::string>& objects) {
             auto o = options;
             o.objects = objects;
             o.validate();
             auto r = std::make_shared<Robot>();
             py::gil_scoped_release release;
             const auto catalogue = sim::ObjectCatalogue::load_default();
             r->robot = std::make_unique<sim::SimulatedRobot>(o, catalogue);
             return r;
           }),
           py::arg("options") = sim::TableOptions{},
           py::arg("objects") = std::vector<std::string>{},
           "Builds the table (objects: catalogue names, or drawn by options.seed).")
      .def(
          "look",
          [](Robot& r) {
            const std::lock_guard lock(r.mutex);
            return look_dict(live(r).look());
          },
          "dict: image (H x W x 3 uint8 RGB), t (s), q (5 joint angles, rad), ee (world, m), "
          "camera (Camera), arm_mask (H x W uint8, 255 on the arm, or None). Copies.")
      .def_property_readonly("camera", [](const Robot& r) { return live(r).camera(); })
      .def(
          "close",
          [](Robot& r) {
            const std::lock_guard lock(r.mutex);
            r.robot.reset();
          },
          "Frees the GL context and the MuJoCo state now (also done at exit); the robot is "
          "unusable after it.")
      .def_property_readonly("joints",
                             [](const Robot& r) { return joints_array(live(r).joints()); })
      .def(
          "push",
          [](Robot& r, const py::handle& start, const py::handle& end, double height, double speed,
             const py::object& episode_dir, double fps, bool overwrite) {
            robot::TablePush p;
            p.start = point2(start, "start");
            p.end = point2(end, "end");
            p.height = height;
            p.speed = speed;
            p.validate();
            const auto rec = recording(episode_dir, fps, overwrite);
            robot::PushReport report;
            {
              py::gil_scoped_release release;
              const std::lock_guard lock(r.mutex);
              report = live(r).push(p, rec);
            }
            return report_dict(report);
          },
          py::arg("start"), py::arg("end"), py::arg("height") = 0.008, py::arg("speed") = 0.05,
          py::arg("episode_dir") = py::none(), py::arg("fps") = 25.0, py::arg("overwrite") = false,
          "A straight push along the table from start to end (world x y, metres), recorded as "
          "an episode when episode_dir is given. GIL released. Returns a report dict.")
      .def(
          "push_image",
          [](Robot& r, const py::handle& start, const py::handle& end, double height, double speed,
             const py::object& episode_dir, double fps, bool overwrite) {
            robot::ImagePush p;
            p.start = point2(start, "start");
            p.end = point2(end, "end");
            p.height = height;
            p.speed = speed;
            const auto rec = recording(episode_dir, fps, overwrite);
            robot::PushReport report;
            {
              py::gil_scoped_release release;
              const std::lock_guard lock(r.mutex);
              report = live(r).push_image(p, rec);
            }
            return report_dict(report);
          },
          py::arg("start"), py::arg("end"), py::arg("height") = 0.008, py::arg("speed") = 0.05,
          py::arg("episode_dir") = py::none(), py::arg("fps") = 25.0, py::arg("overwrite") = false,
          "The same push given in image pixels, back-projected onto the table (eqs 3.13-3.17).")
      .def(
          "ground_truth",
          [](const Robot& r) {
            py::list out;
            for (const auto& o : live(r).ground_truth()) {
              py::dict d;
              d["id"] = o.id;
              d["name"] = o.name;
              d["position"] = array_from_vector(Eigen::VectorXd(o.position));
              d["centre"] = array_from_vector(Eigen::VectorXd(o.centre));
              d["yaw"] = o.yaw;
              d["on_table"] = o.on_table;
              d["upright"] = o.upright;
              out.append(d);
            }
            return out;
          },
          "Ground truth of every object (for scoring only; never the learner's).")
      .def(
          "ground_truth_mask",
          [](Robot& r) {
            const std::lock_guard lock(r.mutex);
            return array_from_image(live(r).ground_truth_mask(), false);
          },
          "Object ids of the current view, H x W uint16 (0 background, 65535 the arm).")
      .def(
          "scatter",
          [](Robot& r, std::uint64_t seed) {
            const std::lock_guard lock(r.mutex);
            py::list out;
            for (const auto& p : live(r).scatter(seed)) {
              out.append(py::make_tuple(p.name, p.position.x(), p.position.y(), p.yaw));
            }
            return out;
          },
          py::arg("seed"),
          "Puts every object at a new random place (seeded); returns "
          "(name, x, y, yaw) of each.")
      .def_property_readonly(
          "table_min",
          [](const Robot& r) { return array_from_vector(Eigen::VectorXd(live(r).table_min())); })
      .def_property_readonly("table_max", [](const Robot& r) {
        return array_from_vector(Eigen::VectorXd(live(r).table_max()));
      });
}

}  // namespace proprio::python
