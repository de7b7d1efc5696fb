// proprio.core: errors, version, the data directory; and the shared numpy conversions.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "common.hpp"
#include "proprio/core/data_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/version.hpp"
#include "proprio/geometry/opencv_runtime.hpp"
#include "proprio/robot/mujoco_runtime.hpp"

namespace proprio::python {

Eigen::MatrixXd matrix_from_array(const py::handle& obj, const char* name, bool finite,
                                  py::ssize_t cols) {
  const auto a = require_array<double>(obj, name, 2, {-1, cols});
  const auto r = a.unchecked<2>();
  Eigen::MatrixXd m(r.shape(0), r.shape(1));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) {
    for (py::ssize_t j = 0; j < r.shape(1); ++j) {
      const double x = r(i, j);
      if (finite && !std::isfinite(x)) {
        throw py::value_error(std::string(name) + ": expected finite values, got " +
                              (std::isnan(x) ? "NaN" : "infinity") + " at row " +
                              std::to_string(i) + ", column " + std::to_string(j));
      }
      m(i, j) = x;
    }
  }
  return m;
}

py::array_t<double> array_from_matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < w.shape(0); ++i) {
    for (py::ssize_t j = 0; j < w.shape(1); ++j) w(i, j) = m(i, j);
  }
  return out;
}

py::array_t<double> array_from_vector(const Eigen::VectorXd& v) {
  py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.data(), v.data() + v.size(), out.mutable_data());
  return out;
}

cv::Mat bgr_from_rgb_array(const py::handle& obj, const char* name) {
  if (!py::isinstance<py::array>(obj)) {
    throw py::value_error(std::string(name) +
                          ": expected an H x W x 3 uint8 RGB array or an H x W uint8 array");
  }
  const auto ndim = py::reinterpret_borrow<py::array>(obj).ndim();
  if (ndim == 2) {
    const auto a = require_array<std::uint8_t>(obj, name, 2);
    return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_8UC1,
                   const_cast<std::uint8_t*>(a.data()))
        .clone();
  }
  const auto a = require_array<std::uint8_t>(obj, name, 3, {-1, -1, 3});
  const cv::Mat rgb(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_8UC3,
                    const_cast<std::uint8_t*>(a.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

namespace {

template <class T>
py::array copy_image(const cv::Mat& image) {
  const int channels = image.channels();
  std::vector<py::ssize_t> shape{image.rows, image.cols};
  if (channels > 1) shape.push_back(channels);
  py::array_t<T> out(shape);
  const std::size_t row_bytes = static_cast<std::size_t>(image.cols) * image.elemSize();
  auto* dst = reinterpret_cast<std::uint8_t*>(out.mutable_data());
  for (int y = 0; y < image.rows; ++y) std::memcpy(dst + y * row_bytes, image.ptr(y), row_bytes);
  return out;
}

}  // namespace

py::array array_from_image(const cv::Mat& image, bool bgr_to_rgb) {
  cv::Mat m = image;
  if (bgr_to_rgb && image.channels() == 3) cv::cvtColor(image, m, cv::COLOR_BGR2RGB);
  switch (m.depth()) {
    case CV_8U:
      return copy_image<std::uint8_t>(m);
    case CV_16U:
      return copy_image<std::uint16_t>(m);
    case CV_32S:
      return copy_image<std::int32_t>(m);
    case CV_32F:
      return copy_image<float>(m);
    case CV_64F:
      return copy_image<double>(m);
    default:
      throw InternalError("array_from_image: unsupported image depth");
  }
}

std::filesystem::path to_path(const py::handle& obj, const char* name) {
  if (!PyUnicode_Check(obj.ptr()) && !py::hasattr(obj, "__fspath__")) {
    throw py::value_error(std::string(name) + ": expected a path (str or os.PathLike), got " +
                          std::string(py::repr(obj)));
  }
  const py::object s = py::module_::import("os").attr("fspath")(obj);
  if (!PyUnicode_Check(s.ptr())) {
    throw py::value_error(std::string(name) + ": expected a str path, got bytes");
  }
  return s.cast<std::string>();
}

core::Provenance python_provenance(std::optional<std::uint64_t> seed) {
  std::vector<std::string> argv{"python3"};
  try {
    for (const auto& a : py::module_::import("sys").attr("argv")) argv.push_back(py::str(a));
  } catch (const py::error_already_set&) {
    // no sys.argv (embedded interpreter): "python3" alone
  }
  auto p = core::Provenance::current(argv, seed);
  p.opencv_version = geometry::opencv_version();
  p.mujoco_version = robot::mujoco_version();
  return p;
}

namespace {

// proprio::Error says "FILE: problem"; a file that could not be opened or does not exist becomes
// OSError (FileNotFoundError when missing), anything else ValueError, with the CLI's one line.
bool is_open_failure(const std::string& message) {
  std::string lower(message);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* key : {"cannot open", "no such ", "does not exist", "cannot read the image",
                          "not found", "permission denied"}) {
    if (lower.find(key) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

void bind_core(py::module_& m) {
  m.doc() = "proprio.core: version, data directory and errors.";
  m.attr("__version__") = proprio::kVersion;
  m.attr("git_commit") = proprio::kGitCommit;
  m.def(
      "data_directory", []() { return core::data_directory().string(); },
      "The directory of proprio's shipped data (models/, objects/, scenarios/): $PROPRIO_DATA_DIR, "
      "beside the program, or the installation's. OSError when none holds it.");
  // pybind11 takes void (*)(std::exception_ptr): the parameter is by value.
  // NOLINTNEXTLINE(performance-unnecessary-value-param)
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      const std::string message = e.what();
      if (is_open_failure(message)) {
        const bool missing = message.find("No such file") != std::string::npos ||
                             message.find("no such") != std::string::npos ||
                             message.find("does not exist") != std::string::npos;
        PyErr_SetString(missing ? PyExc_FileNotFoundError : PyExc_OSError, message.c_str());
      } else {
        PyErr_SetString(PyExc_ValueError, message.c_str());
      }
    } catch (const InternalError& e) {
      PyErr_SetString(PyExc_RuntimeError,
                      (std::string("proprio internal error: ") + e.what()).c_str());
    } catch (const cv::Exception& e) {
      PyErr_SetString(PyExc_ValueError, (std::string("OpenCV: ") + e.what()).c_str());
    }
  });
}

}  // namespace proprio::python
