// proprio._proprio.geometry and .episode: cameras, and recorded interactions read as arrays.
#include <cstring>
#include <limits>

#include "common.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::python {

namespace {

template <class M>
py::array_t<double> fixed_matrix(const M& m) {
  return array_from_matrix(Eigen::MatrixXd(m));
}

}  // namespace

void bind_geometry(py::module_& m) {
  py::class_<geometry::Camera>(
      m, "Camera",
      "A pinhole camera (thesis 3.2; OpenCV's frame: x right, y down, z forward). Extrinsics map "
      "the world (robot base, metres) to the camera: x_cam = R x_world + t, P = K [R | t]. The "
      "matrices are returned as new float64 arrays (copies).")
      .def(py::init([](const py::handle& K, const py::handle& R, const py::handle& t, int width,
                       int height) {
             geometry::Camera c;
             c.K = matrix_from_array(K, "K", true, 3);
             if (c.K.rows() != 3) throw py::value_error("K: expected shape (3, 3)");
             c.R = matrix_from_array(R, "R", true, 3);
             if (c.R.rows() != 3) throw py::value_error("R: expected shape (3, 3)");
             const auto tv = require_array<double>(t, "t", 1, {3});
             c.t = Eigen::Vector3d(tv.at(0), tv.at(1), tv.at(2));
             c.width = width;
             c.height = height;
             return c;
           }),
           py::arg("K"), py::arg("R"), py::arg("t"), py::arg("width") = 0, py::arg("height") = 0)
      .def_property_readonly("K", [](const geometry::Camera& c) { return fixed_matrix(c.K); })
      .def_property_readonly("R", [](const geometry::Camera& c) { return fixed_matrix(c.R); })
      .def_property_readonly(
          "t", [](const geometry::Camera& c) { return array_from_vector(Eigen::VectorXd(c.t)); })
      .def_property_readonly(
          "dist", [](const geometry::Camera& c) { return c.dist; },
          "Lens distortion in OpenCV's order; empty = none.")
      .def_readonly("width", &geometry::Camera::width)
      .def_readonly("height", &geometry::Camera::height)
      .def(
          "P", [](const geometry::Camera& c) { return fixed_matrix(c.P()); },
          "3 x 4 projection K [R | t] (eq 3.7).")
      .def(
          "center", [](const geometry::Camera& c) { return array_from_vector(c.center()); },
          "The optical centre in the world, -R^T t, metres.")
      .def(
          "project",
          [](const geometry::Camera& c, const py::handle& points) {
            const auto X = matrix_from_array(points, "points", true, 3);
            const auto P = c.P();
            Eigen::MatrixXd out(X.rows(), 2);
            for (Eigen::Index i = 0; i < X.rows(); ++i) {
              out.row(i) = geometry::project(P, X.row(i).transpose()).transpose();
            }
            return array_from_matrix(out);
          },
          py::arg("points"),
          "Pixels (N x 2) of world points (N x 3 float64) through P (no lens distortion).")
      .def_static(
          "read",
          [](const py::object& path) { return geometry::read_calib(to_path(path, "path")); },
          py::arg("path"), "Reads a calib.yml.")
      .def("__repr__", [](const geometry::Camera& c) {
        return "Camera(" + std::to_string(c.width) + "x" + std::to_string(c.height) +
               ", fx=" + std::to_string(c.K(0, 0)) + ")";
      });
}

void bind_episode(py::module_& m) {
  py::class_<episode::Episode>(
      m, "Episode",
      "A recorded interaction (docs/formats/episode.md), read and validated once; images are "
      "decoded on demand, each call returning a new array (a copy).")
      .def_static(
          "read",
          [](const py::object& dir) {
            const auto p = to_path(dir, "dir");
            py::gil_scoped_release release;
            return episode::read_episode(p);
          },
          py::arg("dir"), "Reads and validates an episode directory.")
      .def_property_readonly("dir", [](const episode::Episode& e) { return e.dir().string(); })
      .def_property_readonly("frame_count", &episode::Episode::frame_count)
      .def("__len__", &episode::Episode::frame_count)
      .def_property_readonly("has_masks",
                             [](const episode::Episode& e) { return e.info().has_masks; })
      .def_property_readonly("has_depth",
                             [](const episode::Episode& e) { return e.info().has_depth; })
      .def_property_readonly("camera", &episode::Episode::camera)
      .def(
          "frame",
          [](const episode::Episode& e, int i) {
            if (i < 0 || i >= e.frame_count()) throw py::index_error("frame index out of range");
            return array_from_image(e.frame(i));
          },
          py::arg("i"), "Frame i, H x W x 3 uint8 RGB (decoded, BGR -> RGB: a new array).")
      .def(
          "mask",
          [](const episode::Episode& e, int i) {
            if (i < 0 || i >= e.frame_count()) throw py::index_error("frame index out of range");
            return array_from_image(e.mask(i), false);
          },
          py::arg("i"), "Ground-truth object ids of frame i, H x W uint16 (0 background).")
      .def(
          "depth",
          [](const episode::Episode& e, int i) {
            if (i < 0 || i >= e.frame_count()) throw py::index_error("frame index out of range");
            return array_from_image(e.depth(i), false);
          },
          py::arg("i"), "Depth of frame i, H x W uint16 millimetres (0 = unknown).")
      .def(
          "frames",
          [](const episode::Episode& e) {
            const auto& c = e.camera();
            py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(e.frame_count()),
                                           static_cast<py::ssize_t>(c.height),
                                           static_cast<py::ssize_t>(c.width), py::ssize_t{3}});
            for (int i = 0; i < e.frame_count(); ++i) {
              auto f = py::cast<py::array_t<std::uint8_t>>(array_from_image(e.frame(i)));
              if (f.shape(0) != c.height || f.shape(1) != c.width) {
                throw py::value_error(e.dir().string() + ": frame " + std::to_string(i) +
                                      " is not of the camera's size");
              }
              std::memcpy(out.mutable_data(i), f.data(), static_cast<std::size_t>(f.nbytes()));
            }
            return out;
          },
          "Every frame as one N x H x W x 3 uint8 RGB array (decoded into it).")
      .def(
          "arm",
          [](const episode::Episode& e) {
            const auto& a = e.arm();
            const auto n = static_cast<Eigen::Index>(a.size());
            const auto joints = n > 0 ? a[0].q.size() : 0;
            Eigen::MatrixXd q(n, joints);
            Eigen::MatrixXd ee(n, 3);
            Eigen::VectorXd t(n);
            py::array_t<bool> touching(static_cast<py::ssize_t>(n));
            for (Eigen::Index i = 0; i < n; ++i) {
              t(i) = a[i].t;
              q.row(i) = a[i].q.transpose();
              ee.row(i) = a[i].ee.transpose();
              touching.mutable_at(i) = a[i].touching;
            }
            py::dict d;
            d["t"] = array_from_vector(t);
            d["q"] = array_from_matrix(q);
            d["ee"] = array_from_matrix(ee);
            d["touching"] = touching;
            return d;
          },
          "arm.csv as arrays: t (N,) s, q (N x joints) rad, ee (N x 3) m, touching (N,) bool.")
      .def(
          "ee_image_track",
          [](const episode::Episode& e) {
            const auto track = e.ee_image_track();
            Eigen::MatrixXd out(static_cast<Eigen::Index>(track.size()), 2);
            for (std::size_t i = 0; i < track.size(); ++i) {
              const Eigen::Vector2d p =
                  track[i] ? *track[i]
                           : Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
              out.row(static_cast<Eigen::Index>(i)) = p.transpose();
            }
            return array_from_matrix(out);
          },
          "The end effector's image position per frame, N x 2 pixels; NaN where it is behind "
          "the camera.")
      .def_property_readonly("first_touch_frame", &episode::Episode::first_touch_frame)
      .def_property_readonly(
          "objects",
          [](const episode::Episode& e) {
            py::list out;
            for (const auto& o : e.objects()) {
              py::dict d;
              d["id"] = o.id;
              d["name"] = o.name;
              d["role"] = episode::to_string(o.role);
              out.append(d);
            }
            return out;
          },
          "objects.json: id (the mask value), name, role (target, object, arm, distractor).")
      .def("__repr__", [](const episode::Episode& e) {
        return "Episode('" + e.dir().string() + "', frames=" + std::to_string(e.frame_count()) +
               ")";
      });
}

}  // namespace proprio::python
