#include "proprio/topics/topic_distance.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace proprio::topics {

double hellinger(const Eigen::Ref<const Eigen::VectorXd>& p,
                 const Eigen::Ref<const Eigen::VectorXd>& q) {
  assert(p.size() == q.size());
  const double bc = (p.array() * q.array()).sqrt().sum();
  return std::sqrt(std::max(0.0, 1.0 - bc));
}

Eigen::MatrixXd hellinger_matrix(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  assert(a.cols() == b.cols());
  const Eigen::MatrixXd sa = a.array().sqrt();
  const Eigen::MatrixXd sb = b.array().sqrt();
  const Eigen::MatrixXd bc = sa * sb.transpose();
  return (1.0 - bc.array()).max(0.0).sqrt();
}

}  // namespace proprio::topics
