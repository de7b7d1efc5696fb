#include "normalization.hpp"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <cmath>

namespace proprio::geometry::detail {
namespace {

template <int D>
Eigen::Matrix<double, D + 1, D + 1> normalization(
    const std::vector<Eigen::Matrix<double, D, 1>>& points) {
  assert(!points.empty());
  Eigen::Matrix<double, D, 1> centroid = Eigen::Matrix<double, D, 1>::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  double mean_distance = 0.0;
  for (const auto& p : points) mean_distance += (p - centroid).norm();
  mean_distance /= static_cast<double>(points.size());
  assert(mean_distance > 0.0);
  const double s = std::sqrt(static_cast<double>(D)) / mean_distance;
  Eigen::Matrix<double, D + 1, D + 1> T = Eigen::Matrix<double, D + 1, D + 1>::Identity();
  T.template topLeftCorner<D, D>() *= s;
  T.template topRightCorner<D, 1>() = -s * centroid;
  return T;
}

}  // namespace

Eigen::Matrix3d hartley_normalization(const std::vector<Eigen::Vector2d>& points) {
  return normalization<2>(points);
}

Eigen::Matrix4d hartley_normalization(const std::vector<Eigen::Vector3d>& points) {
  return normalization<3>(points);
}

Eigen::Vector3d principal_spread(const std::vector<Eigen::Vector3d>& points) {
  assert(!points.empty());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& p : points) C += (p - centroid) * (p - centroid).transpose();
  C /= static_cast<double>(points.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ev = eig.eigenvalues().cwiseMax(0.0);  // ascending
  return {std::sqrt(ev(2)), std::sqrt(ev(1)), std::sqrt(ev(0))};
}

}  // namespace proprio::geometry::detail
