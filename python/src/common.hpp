#pragma once
// Shared pieces of the Python bindings: array checks that name the argument, conversions between
// numpy and Eigen / OpenCV, and the generic binding of an Options struct from its describe().

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::python {

namespace py = pybind11;

/// A JSON value (a library record) as Python objects (dicts, lists, numbers, strings, None).
inline py::object json_to_python(const core::Json& json) {
  return py::module_::import("json").attr("loads")(json.dump());
}

/// "float64", "int32", ...: the numpy name of T.
template <class T>
std::string dtype_name() {
  return py::str(py::dtype::of<T>().attr("name"));
}

/// Checks that `obj` is a numpy array of dtype T, C-contiguous, with `ndim` dimensions (and, where
/// an entry of `shape` is >= 0, that size); throws ValueError naming `name` and what was expected.
template <class T>
py::array_t<T, py::array::c_style> require_array(const py::handle& obj, const char* name, int ndim,
                                                 std::vector<py::ssize_t> shape = {}) {
  const std::string expected =
      std::to_string(ndim) + "-d C-contiguous " + dtype_name<T>() + " array";
  if (!py::isinstance<py::array>(obj)) {
    throw py::value_error(std::string(name) + ": expected a " + expected + ", got " +
                          std::string(py::str(obj.get_type().attr("__name__"))));
  }
  auto a = py::reinterpret_borrow<py::array>(obj);
  if (!a.dtype().is(py::dtype::of<T>())) {
    throw py::value_error(std::string(name) + ": expected a " + expected + ", got dtype " +
                          std::string(py::str(a.dtype().attr("name"))));
  }
  if (a.ndim() != ndim) {
    throw py::value_error(std::string(name) + ": expected a " + expected + ", got " +
                          std::to_string(a.ndim()) + " dimensions");
  }
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (shape[i] >= 0 && a.shape(static_cast<py::ssize_t>(i)) != shape[i]) {
      throw py::value_error(std::string(name) + ": expected size " + std::to_string(shape[i]) +
                            " along axis " + std::to_string(i) + ", got " +
                            std::to_string(a.shape(static_cast<py::ssize_t>(i))));
    }
  }
  if (!(a.flags() & py::array::c_style)) {
    throw py::value_error(std::string(name) + ": expected a " + expected +
                          ", got a non-contiguous array (use numpy.ascontiguousarray)");
  }
  return py::reinterpret_borrow<py::array_t<T, py::array::c_style>>(a);
}

/// A row-major Eigen matrix (copied) from a 2-d float64 C-contiguous array; with `finite`, NaN or
/// infinity is a ValueError naming the argument.
Eigen::MatrixXd matrix_from_array(const py::handle& obj, const char* name, bool finite = true,
                                  py::ssize_t cols = -1);
/// A new float64 array (copy) of an Eigen matrix.
py::array_t<double> array_from_matrix(const Eigen::MatrixXd& m);
py::array_t<double> array_from_vector(const Eigen::VectorXd& v);

/// A cv::Mat header over a C-contiguous uint8 H x W x 3 RGB image (copied to BGR, the library's
/// order), or H x W grey. ValueError naming `name` otherwise.
cv::Mat bgr_from_rgb_array(const py::handle& obj, const char* name);
/// H x W x 3 uint8 RGB (copy, BGR -> RGB) or H x W for one channel, of any 8U/32F/64F/16U/32S Mat.
py::array array_from_image(const cv::Mat& image, bool bgr_to_rgb = true);

/// os.fspath(obj) as a path; ValueError naming `name` unless str or os.PathLike.
std::filesystem::path to_path(const py::handle& obj, const char* name);

/// The provenance of a result written from Python: this build, "python3 <sys.argv>", the linked
/// OpenCV's and MuJoCo's versions.
core::Provenance python_provenance(std::optional<std::uint64_t> seed);

void bind_core(py::module_& m);
void bind_topics(py::module_& m);
void bind_features(py::module_& m);
void bind_geometry(py::module_& m);
void bind_episode(py::module_& m);
void bind_vision(py::module_& m);
void bind_sim(py::module_& m);
void bind_planning(py::module_& m);
void bind_loop(py::module_& m);

}  // namespace proprio::python
