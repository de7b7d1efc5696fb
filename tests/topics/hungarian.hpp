#pragma once
// One-to-one matching of topics by least total distance, through dlib's Hungarian algorithm.

#include <Eigen/Core>
#include <cmath>
#include <vector>

#ifdef PROPRIO_HAVE_DLIB
#include <dlib/optimization/max_cost_assignment.h>
#endif

namespace proprio::test {

/// assignment[i] = the column matched to row i, minimising the sum of cost(i, assignment[i]).
/// Empty when dlib is missing. dlib wants integer costs: distances are scaled by 1e6.
inline std::vector<long> min_cost_assignment(const Eigen::MatrixXd& cost) {
#ifdef PROPRIO_HAVE_DLIB
  const long n = cost.rows();
  dlib::matrix<long> c(n, n);
  for (long i = 0; i < n; ++i) {
    for (long j = 0; j < n; ++j) c(i, j) = -std::lround(cost(i, j) * 1e6);
  }
  return dlib::max_cost_assignment(c);
#else
  (void)cost;
  return {};
#endif
}

}  // namespace proprio::test
