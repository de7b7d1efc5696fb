#include "proprio/geometry/camera.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <string>
#include <string_view>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/text.hpp"
#include "proprio/core/yaml_depth.hpp"

namespace proprio::geometry {

Matrix34d Camera::P() const {
  Matrix34d Rt;
  Rt << R, t;
  return K * Rt;
}

Eigen::Vector3d Camera::center() const { return -R.transpose() * t; }

Eigen::Vector2d Camera::project(const Eigen::Vector3d& X) const {
  return geometry::project(P(), X);
}

double Camera::depth(const Eigen::Vector3d& X) const { return (R * X + t).z(); }

bool Camera::has_distortion() const {
  for (double d : dist) {
    if (d != 0.0) return true;
  }
  return false;
}

Eigen::Vector2d project(const Matrix34d& P, const Eigen::Vector3d& X) {
  const Eigen::Vector3d x = P * X.homogeneous();
  return x.hnormalized();
}

Eigen::Matrix<double, 2, 3> projection_jacobian(const Matrix34d& P, const Eigen::Vector3d& X) {
  const Eigen::Vector3d y = P * X.homogeneous();
  const double u = y.x() / y.z();
  const double v = y.y() / y.z();
  Eigen::Matrix<double, 2, 3> J;
  J.row(0) = P.block<1, 3>(0, 0) - u * P.block<1, 3>(2, 0);
  J.row(1) = P.block<1, 3>(1, 0) - v * P.block<1, 3>(2, 0);
  return J / y.z();
}

std::vector<Eigen::Vector2d> undistort_pixels(const Camera& camera,
                                              const std::vector<Eigen::Vector2d>& pixels) {
  if (!camera.has_distortion() || pixels.empty()) return pixels;
  std::vector<cv::Point2d> in(pixels.size());
  for (size_t i = 0; i < pixels.size(); ++i) in[i] = {pixels[i].x(), pixels[i].y()};
  cv::Mat K;
  cv::eigen2cv(camera.K, K);
  std::vector<cv::Point2d> out;
  // The default 5 fixed-point iterations leave up to a pixel of error near the image corners of a
  // wide lens; iterate until the residual is negligible instead.
  cv::undistortPoints(
      in, out, K, camera.dist, cv::noArray(), K,
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  std::vector<Eigen::Vector2d> result(out.size());
  for (size_t i = 0; i < out.size(); ++i) result[i] = {out[i].x, out[i].y};
  return result;
}

Camera decompose_projection(const Matrix34d& P_in) {
  Matrix34d P = P_in;
  const Eigen::Matrix3d M = P.leftCols<3>();
  if (!P.allFinite() || std::abs(M.determinant()) < 1e-12 * std::pow(M.norm(), 3)) {
    throw Error("projection matrix has a singular left 3x3 block: not a finite camera");
  }
  // P is defined up to scale: choose the sign that makes det(M) > 0, so that R is a rotation.
  if (M.determinant() < 0) P = -P;
  // RQ decomposition of M = K R through the QR decomposition of the row-reversed transpose.
  Eigen::Matrix3d flip;
  flip << 0, 0, 1, 0, 1, 0, 1, 0, 0;
  const Eigen::Matrix3d A = (flip * P.leftCols<3>()).transpose();
  Eigen::HouseholderQR<Eigen::Matrix3d> qr(A);
  const Eigen::Matrix3d Q = qr.householderQ();
  const Eigen::Matrix3d Rr = qr.matrixQR().triangularView<Eigen::Upper>();
  Eigen::Matrix3d K = flip * Rr.transpose() * flip;
  Eigen::Matrix3d R = flip * Q.transpose();
  // Make K's diagonal positive; D = diag(+-1) with D D = I keeps K R unchanged.
  const Eigen::Vector3d s = K.diagonal().cwiseSign();
  const Eigen::Matrix3d D = s.asDiagonal();
  K = K * D;
  R = D * R;
  Camera cam;
  const double scale = K(2, 2);
  cam.K = K / scale;
  cam.R = R;
  cam.t = K.inverse() * P.col(3);
  if (R.determinant() < 0) {  // cannot happen when det(M) > 0, kept as a guard against rounding
    throw Error("projection matrix decomposes into an improper rotation");
  }
  return cam;
}

namespace {

// The largest side of a matrix in calib.yml (dist_coeffs has up to 14 values).
constexpr int kMaxCalibMatrixSide = 16;

Eigen::MatrixXd read_matrix(const cv::FileStorage& fs, const std::string& key,
                            const std::filesystem::path& path, int rows, int cols, bool required) {
  const cv::FileNode node = fs[key];
  if (node.empty()) {
    if (required) throw Error::in_file(path, "missing '" + key + "'");
    return {};
  }
  // OpenCV allocates rows x cols as declared before it reads the data: a bogus size ("rows: Y3",
  // found by fuzz_calib) asked for 64 GB. Calibration matrices are small; check the declaration.
  if (node.isMap()) {
    const cv::FileNode r = node["rows"];
    const cv::FileNode c = node["cols"];
    const cv::FileNode data = node["data"];
    const bool sane = r.isInt() && c.isInt() && static_cast<int>(r) >= 1 &&
                      static_cast<int>(r) <= kMaxCalibMatrixSide && static_cast<int>(c) >= 1 &&
                      static_cast<int>(c) <= kMaxCalibMatrixSide && data.isSeq() &&
                      data.size() == static_cast<std::size_t>(static_cast<int>(r)) *
                                         static_cast<std::size_t>(static_cast<int>(c));
    if (!sane) {
      throw Error::in_file(path, "'" + key + "' is not a matrix (rows, cols and data disagree)");
    }
  } else if (node.isSeq() && node.size() > static_cast<std::size_t>(kMaxCalibMatrixSide)) {
    throw Error::in_file(path, "'" + key + "' has too many values");
  }
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception& e) {
    throw Error::in_file(path, "'" + key + "' is not a matrix: " + e.err);
  }
  if (m.empty()) throw Error::in_file(path, "'" + key + "' is not a matrix");
  if (rows > 0 && (m.rows != rows || m.cols != cols)) {
    throw Error::in_file(path, "'" + key + "' is " + std::to_string(m.rows) + "x" +
                                   std::to_string(m.cols) + ", expected " + std::to_string(rows) +
                                   "x" + std::to_string(cols));
  }
  m.convertTo(m, CV_64F);
  Eigen::MatrixXd e;
  cv::cv2eigen(m, e);
  if (!e.allFinite()) throw Error::in_file(path, "'" + key + "' holds NaN or inf");
  return e;
}

// OpenCV 4.6's YAML parser (FileStorage::Impl, parse()) assumes that whatever follows the first
// document's top-level collection starts with "---" or "...", skips three bytes blindly and, when
// the next byte is a '-' that does not start "---", loops for ever (found by fuzz_triangulate:
// "%YAML:1.0\n---L:1\n--\n-", "---\n- 1\n...\n-", "---\n[1]\n-\n-"). That parser is not ours to
// fix, so the text is held to the layout OpenCV itself writes before it sees it: directives and
// one "---" line, then one block map whose keys start at column 0, optionally closed by "..." with
// nothing after it. A block map at column 0 only ends at "..." or at the end of the text, so
// parse() never reaches the blind skip with text left.
void check_calib_layout(std::string_view text, const std::filesystem::path& path) {
  bool in_map = false;
  bool closed = false;
  long line = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    ++line;
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t')) {
      l.remove_suffix(1);
    }
    const std::size_t first = l.find_first_not_of(" \t");
    if (first == std::string_view::npos || l[first] == '#') continue;  // blank or comment
    if (closed) {
      throw Error::at_line(path, line, "text after the end of the document ('...')");
    }
    if (!in_map) {
      if (l[0] == '%') continue;  // a directive (%YAML:1.0)
      if (l == "---") continue;
      if (l.starts_with("---") || l.starts_with("...")) {
        throw Error::at_line(path, line,
                             "not a calibration (its map must begin on the line after '---')");
      }
      if (first != 0) {
        throw Error::at_line(path, line, "not a calibration (its keys must start at column 0)");
      }
      if (l[0] == '-' || l[0] == '[' || l[0] == '{') {
        throw Error::in_file(path, "not a calibration (the top level is not a map)");
      }
      in_map = true;
      continue;
    }
    if (l.starts_with("---")) {
      throw Error::at_line(path, line, "more than one YAML document (a calibration is one map)");
    }
    if (l.starts_with("...")) closed = true;
  }
}

}  // namespace

Camera read_calib(const std::filesystem::path& path) {
  const std::string text = core::read_file(path);
  // OpenCV's parser recurses on nested values: bound the nesting before it sees the text.
  core::check_yaml_depth(text, path);
  check_calib_layout(text, path);
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    // OpenCV 4.6 swaps a parse error's fields: err holds its own function's name ("parseValue")
    // and func "(LINE): problem". The user gets the line and the problem, not the name.
    const std::string& where = e.code == cv::Error::StsParseError ? e.func : e.err;
    if (e.code == cv::Error::StsParseError && where.size() > 3 && where[0] == '(') {
      char* end = nullptr;
      const long line = std::strtol(where.c_str() + 1, &end, 10);
      if (end != nullptr && end[0] == ')' && end[1] == ':' && line > 0) {
        const char* said = end + 2;
        while (*said == ' ') ++said;
        std::string problem = "not an OpenCV YAML file: ";
        problem += said;
        throw Error::at_line(path, line, problem);
      }
    }
    throw Error::in_file(path, "not an OpenCV YAML file: " + e.err);
  } catch (const std::exception& e) {
    // OpenCV's YAML parser throws std::length_error on some malformed keys (found by fuzz_calib):
    // bad input, not a bug of proprio's.
    throw Error::in_file(
        path, std::string("not an OpenCV YAML file (its parser failed: ") + e.what() + ")");
  }
  if (!fs.isOpened()) throw Error::in_file(path, "not an OpenCV YAML file");
  // Looking a key up in anything but a map is an OpenCV assertion (found by fuzz_calib).
  if (!fs.root().isMap())
    throw Error::in_file(path, "not a calibration (the top level is not a map)");
  if (!fs["format_version"].empty()) {
    const cv::FileNode v = fs["format_version"];
    if (!v.isInt()) throw Error::in_file(path, "'format_version' is not an integer");
    if (static_cast<int>(v) > kCalibFormatVersion || static_cast<int>(v) < 1) {
      throw Error::in_file(path, "format_version " + std::to_string(static_cast<int>(v)) +
                                     " is not supported (this build reads 1.." +
                                     std::to_string(kCalibFormatVersion) + ")");
    }
  }
  const bool has_k = !fs["camera_matrix"].empty();
  const Eigen::MatrixXd P = read_matrix(fs, "P", path, 3, 4, !has_k);
  Camera cam;
  if (has_k) {
    cam.K = read_matrix(fs, "camera_matrix", path, 3, 3, true);
    cam.R = read_matrix(fs, "R", path, 3, 3, true);
    cam.t = read_matrix(fs, "t", path, 3, 1, true);
  } else {
    cam = decompose_projection(P);
  }
  if (!fs["dist_coeffs"].empty()) {
    const Eigen::MatrixXd d = read_matrix(fs, "dist_coeffs", path, 0, 0, true);
    if (d.size() != 4 && d.size() != 5 && d.size() != 8 && d.size() != 12 && d.size() != 14) {
      throw Error::in_file(path, "'dist_coeffs' has " + std::to_string(d.size()) +
                                     " values, expected 4, 5, 8, 12 or 14");
    }
    cam.dist.assign(d.data(), d.data() + d.size());
  }
  // OpenCV reads a string as INT_MAX when asked for an int: check the type first.
  for (const char* key : {"image_width", "image_height"}) {
    const cv::FileNode n = fs[key];
    if (n.empty()) continue;
    if (!n.isInt()) throw Error::in_file(path, std::string("'") + key + "' is not an integer");
    const int v = static_cast<int>(n);
    if (v < 0 || v > kMaxCalibImageSide) {
      throw Error::in_file(path, std::string("'") + key + "' = " + std::to_string(v) +
                                     " is outside [0, " + std::to_string(kMaxCalibImageSide) + "]");
    }
    (std::string_view(key) == "image_width" ? cam.width : cam.height) = v;
  }
  if (cam.t.stableNorm() > kMaxCalibTranslation || cam.K.cwiseAbs().maxCoeff() > kMaxCalibPixels) {
    throw Error::in_file(path, "absurd calibration: |t| = " + core::num(cam.t.stableNorm()) +
                                   " (at most " + core::num(kMaxCalibTranslation) +
                                   "), largest entry of K " +
                                   core::num(cam.K.cwiseAbs().maxCoeff()) + " (at most " +
                                   core::num(kMaxCalibPixels) + ")");
  }
  if (cam.K(0, 0) <= 0 || cam.K(1, 1) <= 0 || std::abs(cam.K(2, 2) - 1.0) > 1e-9 ||
      cam.K(1, 0) != 0 || cam.K(2, 0) != 0 || cam.K(2, 1) != 0) {
    throw Error::in_file(path,
                         "'camera_matrix' must be upper triangular with positive focal lengths "
                         "and K(2,2) = 1");
  }
  const double ortho = (cam.R * cam.R.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (ortho > 1e-6 || cam.R.determinant() < 0) {
    throw Error::in_file(
        path, "'R' is not a rotation matrix (|R R^T - I| = " + std::to_string(ortho) + ")");
  }
  if (has_k && P.size() == 12) {
    // P may be stored at any scale: compare directions.
    const Matrix34d Pk = cam.P();
    const double scale = Pk.norm() / P.norm();
    const double sign = (Pk.array() * P.array()).sum() < 0 ? -1.0 : 1.0;
    const double rel = (Pk - sign * scale * P).norm() / Pk.norm();
    if (rel > 1e-6) {
      throw Error::in_file(path, "'P' disagrees with camera_matrix [R | t] (relative difference " +
                                     std::to_string(rel) + ")");
    }
  }
  return cam;
}

void write_calib(const std::filesystem::path& path, const Camera& cam,
                 const std::optional<core::Provenance>& provenance) {
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "format"
     << "proprio.calib"
     << "format_version" << kCalibFormatVersion;
  cv::Mat K, R, t, P;
  cv::eigen2cv(cam.K, K);
  cv::eigen2cv(cam.R, R);
  cv::eigen2cv(cam.t, t);
  const Matrix34d Pm = cam.P();
  cv::eigen2cv(Pm, P);
  fs << "camera_matrix" << K;
  fs << "dist_coeffs" << cv::Mat(cam.dist.empty() ? std::vector<double>(5, 0.0) : cam.dist, true);
  fs << "R" << R << "t" << t << "P" << P;
  if (cam.width > 0) fs << "image_width" << cam.width << "image_height" << cam.height;
  if (provenance) {
    const core::Json j = core::to_json(*provenance);
    fs << "provenance"
       << "{";
    for (const auto& [key, value] : j.items()) {
      fs << key << (value.is_string() ? value.get<std::string>() : value.dump());
    }
    fs << "}";
  }
  core::write_file_atomic(path, fs.releaseAndGetString());
}

}  // namespace proprio::geometry
