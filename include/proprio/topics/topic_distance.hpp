#pragma once
// Distances between discrete distributions, for comparing topics.

#include <Eigen/Core>

namespace proprio::topics {

/// Hellinger distance sqrt(1 - sum_i sqrt(p_i q_i)) between two distributions (each sums to 1);
/// in [0, 1].
double hellinger(const Eigen::Ref<const Eigen::VectorXd>& p,
                 const Eigen::Ref<const Eigen::VectorXd>& q);

/// The matrix of Hellinger distances between the rows of a (n x W) and the rows of b (m x W).
Eigen::MatrixXd hellinger_matrix(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace proprio::topics
