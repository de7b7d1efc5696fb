#pragma once
// k-means++ seeding (Arthur & Vassilvitskii 2007) over the rows of a small matrix, shared by the
// Mixture of Topics' unsupervised clustering and the Dirichlet mixture's EM starts. Written here
// (a few lines over Eigen): the features module's k-means is for descriptors and would make
// topics depend on it.

#include <Eigen/Core>
#include <cstdint>

#include "proprio/core/random.hpp"

namespace proprio::topics::detail {

/// k rows of x as starting centres: the first uniformly at random, each next with probability
/// proportional to its squared distance to the nearest centre so far (uniform when every row
/// coincides with a centre). x has at least one row; k >= 1.
inline Eigen::MatrixXd kmeans_pp_seeds(const Eigen::MatrixXd& x, int k, core::Rng& rng) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd centres(k, x.cols());
  centres.row(0) = x.row(static_cast<Eigen::Index>(rng.index(static_cast<std::uint64_t>(n))));
  Eigen::VectorXd d2 = (x.rowwise() - centres.row(0)).rowwise().squaredNorm();
  for (int j = 1; j < k; ++j) {
    const double total = d2.sum();
    Eigen::Index pick = 0;
    if (total > 0) {
      double u = rng.uniform() * total;
      for (pick = 0; pick < n - 1; ++pick) {
        u -= d2(pick);
        if (u < 0) break;
      }
    } else {
      pick = static_cast<Eigen::Index>(rng.index(static_cast<std::uint64_t>(n)));
    }
    centres.row(j) = x.row(pick);
    d2 = d2.cwiseMin((x.rowwise() - centres.row(j)).rowwise().squaredNorm());
  }
  return centres;
}

}  // namespace proprio::topics::detail
