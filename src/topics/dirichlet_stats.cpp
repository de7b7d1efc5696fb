#include "proprio/topics/dirichlet_stats.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "proprio/core/error.hpp"

namespace proprio::topics {

namespace {

[[noreturn]] void bad_row(const char* what, Eigen::Index row, const std::string& problem) {
  std::ostringstream m;
  m << what << ": row " << row << ": " << problem;
  throw Error(m.str());
}

std::string entry(Eigen::Index k, double v) {
  std::ostringstream m;
  m.precision(17);
  m << "entry " << k << " is " << v;
  return m.str();
}

}  // namespace

void ProportionOptions::validate() const {
  if (!(floor >= 1e-300 && floor <= 1e-2)) {
    throw Error("Dirichlet proportions: floor must be in [1e-300, 1e-2], not " +
                std::to_string(floor));
  }
  if (!(sum_tolerance >= 0.0 && sum_tolerance < 0.5)) {
    throw Error("Dirichlet proportions: sum_tolerance must be in [0, 0.5), not " +
                std::to_string(sum_tolerance));
  }
}

DirichletStats::DirichletStats(int dim) {
  if (!(dim >= 1))
    throw Error("DirichletStats: the dimension must be at least 1, not " + std::to_string(dim));
  mean_log_ = Eigen::VectorXd::Zero(dim);
}

DirichletStats DirichletStats::of_proportions(const Eigen::Ref<const Eigen::MatrixXd>& proportions,
                                              const ProportionOptions& options) {
  options.validate();
  constexpr const char* kWhat = "Dirichlet proportions";
  const Eigen::Index n = proportions.rows();
  const Eigen::Index T = proportions.cols();
  DirichletStats s(static_cast<int>(T));
  if (n == 0) return s;
  const auto a = proportions.array();
  // The checks in bulk first (fast, vectorised); the row-by-row search only to name a bad row.
  if (!((a >= 0.0) && (a <= 1.0)).all()) {
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index k = 0; k < T; ++k) {
        const double v = proportions(i, k);
        if (!(v >= 0.0 && v <= 1.0)) bad_row(kWhat, i, entry(k, v) + ", not in [0, 1]");
      }
    }
  }
  const Eigen::VectorXd sums = proportions.rowwise().sum();
  if (!((sums.array() - 1.0).abs() <= options.sum_tolerance).all()) {
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!(std::abs(sums(i) - 1.0) <= options.sum_tolerance)) {
        std::ostringstream m;
        m.precision(12);
        m << "sums to " << sums(i) << ", not 1 within " << options.sum_tolerance;
        bad_row(kWhat, i, m.str());
      }
    }
  }
  for (Eigen::Index k = 0; k < T; ++k) {
    const auto col = proportions.col(k).array();
    s.clamped_ += (col < options.floor).count();
    s.mean_log_(k) = col.max(options.floor).log().sum() / static_cast<double>(n);
  }
  s.count_ = static_cast<double>(n);
  return s;
}

DirichletStats DirichletStats::of_log_proportions(
    const Eigen::Ref<const Eigen::MatrixXd>& log_proportions, const ProportionOptions& options) {
  options.validate();
  constexpr const char* kWhat = "Dirichlet log-proportions";
  const Eigen::Index n = log_proportions.rows();
  const Eigen::Index T = log_proportions.cols();
  DirichletStats s(static_cast<int>(T));
  if (n == 0) return s;
  const auto a = log_proportions.array();
  if (!(a <= options.sum_tolerance).all()) {  // NaN and +inf fail too
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index k = 0; k < T; ++k) {
        const double v = log_proportions(i, k);
        if (!(v <= options.sum_tolerance))
          bad_row(kWhat, i, entry(k, v) + ", not a log-proportion");
      }
    }
  }
  const Eigen::VectorXd top = log_proportions.rowwise().maxCoeff();
  Eigen::ArrayXd sum = Eigen::ArrayXd::Zero(n);
  for (Eigen::Index k = 0; k < T; ++k) sum += (log_proportions.col(k).array() - top.array()).exp();
  const Eigen::ArrayXd lse = top.array() + sum.log();  // -inf rows give NaN: rejected below
  if (!(lse.abs() <= options.sum_tolerance).all()) {
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!(std::abs(lse(i)) <= options.sum_tolerance)) {
        std::ostringstream m;
        m.precision(12);
        m << "logsumexp is " << lse(i) << ", not 0 within " << options.sum_tolerance
          << " (the proportions do not sum to 1)";
        bad_row(kWhat, i, m.str());
      }
    }
  }
  // Only exact zeros (-inf) are floored: finite log-proportions are taken as they are, however
  // small (that is what log space is for).
  const double log_floor = std::log(options.floor);
  for (Eigen::Index k = 0; k < T; ++k) {
    const auto col = log_proportions.col(k).array();
    const auto zero = col == -std::numeric_limits<double>::infinity();
    s.clamped_ += zero.count();
    s.mean_log_(k) = zero.select(log_floor, col).sum() / static_cast<double>(n);
  }
  s.count_ = static_cast<double>(n);
  return s;
}

void DirichletStats::add_log(const Eigen::Ref<const Eigen::VectorXd>& log_p, double weight) {
  if (!(std::isfinite(weight) && weight > 0.0))
    throw Error("DirichletStats::add_log: the weight must be positive and finite, not " +
                std::to_string(weight));
  if (dim() == 0) mean_log_ = Eigen::VectorXd::Zero(log_p.size());
  if (!(log_p.size() == mean_log_.size() && log_p.size() >= 1))
    throw Error("DirichletStats::add_log: a sample of size " + std::to_string(log_p.size()) +
                " for statistics of dimension " + std::to_string(mean_log_.size()));
  for (Eigen::Index k = 0; k < log_p.size(); ++k) {
    if (!(std::isfinite(log_p(k))))
      throw Error("DirichletStats::add_log: " + entry(k, log_p(k)) + ", not finite");
  }
  count_ += weight;
  mean_log_ += (weight / count_) * (log_p - mean_log_);
}

void DirichletStats::merge(const DirichletStats& other) {
  if (other.count_ == 0.0) {
    clamped_ += other.clamped_;
    if (dim() == 0) mean_log_ = Eigen::VectorXd::Zero(other.dim());
    return;
  }
  if (count_ == 0.0) {
    if (!(dim() == 0 || dim() == other.dim()))
      throw Error("DirichletStats::merge: dimensions " + std::to_string(dim()) + " and " +
                  std::to_string(other.dim()));
    const std::int64_t c = clamped_;
    *this = other;
    clamped_ += c;
    return;
  }
  if (!(dim() == other.dim()))
    throw Error("DirichletStats::merge: dimensions " + std::to_string(dim()) + " and " +
                std::to_string(other.dim()));
  const double total = count_ + other.count_;
  mean_log_ = (count_ / total) * mean_log_ + (other.count_ / total) * other.mean_log_;
  count_ = total;
  clamped_ += other.clamped_;
}

void DirichletStats::scale(double factor) {
  if (!(factor > 0.0 && factor <= 1.0))
    throw Error("DirichletStats::scale: the factor must be in (0, 1], not " +
                std::to_string(factor));
  count_ *= factor;
}

}  // namespace proprio::topics
