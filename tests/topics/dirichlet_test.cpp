// The Dirichlet building block (thesis 7.1; Minka 2003): log density against scipy, sampling,
// sufficient statistics, and the maximum-likelihood fit on random problems, known answers and the
// degenerate inputs that break other implementations.
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/special_functions/digamma.hpp>
#include <boost/math/special_functions/trigamma.hpp>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "../support/error_of.hpp"
#include "../support/paths.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_fit.hpp"
#include "proprio/topics/dirichlet_stats.hpp"
#include "special_functions.hpp"

namespace proprio::topics {
namespace {

using test::error_of;

::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << '"' << text << "\" does not contain \"" << part << '"';
}

Eigen::VectorXd random_alpha(core::Rng& rng, int dim, double lo, double hi) {
  Eigen::VectorXd a(dim);
  for (int k = 0; k < dim; ++k) a(k) = std::exp(rng.uniform(std::log(lo), std::log(hi)));
  return a;
}

double max_relative_error(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
  return ((got - want).array().abs() / want.array()).maxCoeff();
}

// --- special functions --------------------------------------------------------------------------

TEST(DirichletSpecialFunctions, DigammaAndTrigammaMatchBoost) {
  for (double x = 1e-6; x < 1e6; x *= 1.37) {
    const double d = boost::math::digamma(x);
    const double t = boost::math::trigamma(x);
    EXPECT_NEAR(detail::digamma(x), d, 1e-14 * std::max(1.0, std::abs(d))) << x;
    EXPECT_NEAR(detail::trigamma(x), t, 1e-14 * t) << x;
  }
}

TEST(DirichletSpecialFunctions, InverseDigammaInvertsDigamma) {
  for (double x = 1e-8; x < 1e8; x *= 1.61) {
    EXPECT_NEAR(detail::inverse_digamma(detail::digamma(x)), x, 1e-12 * x) << x;
  }
  EXPECT_NEAR(detail::inverse_digamma(-0.5772156649015329), 1.0, 1e-14);
}

// --- the distribution ---------------------------------------------------------------------------

TEST(Dirichlet, MeanPrecisionAndMeanLogKnownAnswers) {
  const Dirichlet d(Eigen::Vector3d(1.0, 2.0, 5.0));
  EXPECT_DOUBLE_EQ(d.precision(), 8.0);
  EXPECT_EQ(d.dim(), 3);
  EXPECT_TRUE(d.mean().isApprox(Eigen::Vector3d(0.125, 0.25, 0.625), 1e-15));
  // Dir(1, 1): uniform on the segment, E[log p] = psi(1) - psi(2) = -1, density 1.
  const Dirichlet flat(Eigen::Vector2d(1.0, 1.0));
  EXPECT_NEAR(flat.mean_log()(0), -1.0, 1e-15);
  EXPECT_NEAR(flat.log_density(Eigen::Vector2d(0.3, 0.7)), 0.0, 1e-15);
  // Dir(2, 1, 1) at p: Gamma(4) / Gamma(2) * p_0 = 6 p_0.
  const Dirichlet d2(Eigen::Vector3d(2.0, 1.0, 1.0));
  EXPECT_NEAR(d2.log_density(Eigen::Vector3d(0.2, 0.3, 0.5)), std::log(1.2), 1e-14);
  EXPECT_NEAR(d2.log_density_of_log(Eigen::Vector3d(0.2, 0.3, 0.5).array().log()), std::log(1.2),
              1e-14);
}

TEST(Dirichlet, RejectsBadAlpha) {
  EXPECT_TRUE(has(error_of([] { Dirichlet(Eigen::VectorXd::Ones(1)); }), "at least 2"));
  EXPECT_TRUE(has(error_of([] { Dirichlet(Eigen::Vector3d(1.0, 0.0, 1.0)); }), "alpha[1]"));
  EXPECT_TRUE(has(
      error_of([] { Dirichlet(Eigen::Vector2d(1.0, std::numeric_limits<double>::quiet_NaN())); }),
      "alpha[1]"));
}

// Fixture written by scripts/make-dirichlet-fixture with scipy.stats.dirichlet.logpdf.
TEST(Dirichlet, LogDensityMatchesScipy) {
  const auto path = test::source_dir() / "tests/topics/data/dirichlet_logpdf.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::string line;
  int cases = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    int dim = 0;
    s >> dim;
    ASSERT_GE(dim, 2);
    Eigen::VectorXd alpha(dim);
    Eigen::VectorXd x(dim);
    for (int k = 0; k < dim; ++k) s >> alpha(k);
    for (int k = 0; k < dim; ++k) s >> x(k);
    double want = 0.0;
    s >> want;
    ASSERT_FALSE(s.fail()) << line;
    const Dirichlet d(alpha);
    const double tol = 1e-9 * std::max(1.0, std::abs(want));
    EXPECT_NEAR(d.log_density(x), want, tol) << "case " << cases;
    EXPECT_NEAR(d.log_density_of_log(x.array().log().matrix()), want, tol) << "case " << cases;
    ++cases;
  }
  EXPECT_GE(cases, 100);
}

TEST(Dirichlet, SamplingIsDeterministicAndStaysInLogSpace) {
  const Dirichlet d(Eigen::Vector4d(1e-3, 0.5, 3.0, 1e3));
  core::Rng a(42);
  core::Rng b(42);
  const Eigen::MatrixXd sa = d.sample_log(a, 50);
  const Eigen::MatrixXd sb = d.sample_log(b, 50);
  EXPECT_EQ(sa, sb);
  core::Rng c(43);
  EXPECT_NE(sa, d.sample_log(c, 50));
  for (Eigen::Index i = 0; i < sa.rows(); ++i) {
    ASSERT_TRUE(sa.row(i).allFinite()) << i;
    const double top = sa.row(i).maxCoeff();
    EXPECT_NEAR(top + std::log((sa.row(i).array() - top).exp().sum()), 0.0, 1e-12);
  }
  // alpha = 1e-3: log p is typically hundreds of nats below 0, where exp underflows.
  EXPECT_LT(sa.col(0).minCoeff(), -745.0);
}

TEST(Dirichlet, SampleMeansMatchTheMoments) {
  const Eigen::Vector3d alpha(0.2, 1.5, 6.0);
  const Dirichlet d(alpha);
  core::Rng rng(5);
  const Eigen::MatrixXd logs = d.sample_log(rng, 40000);
  const Eigen::VectorXd mean_log = logs.colwise().mean();
  const Eigen::VectorXd mean = logs.array().exp().colwise().mean();
  EXPECT_LT((mean - d.mean()).cwiseAbs().maxCoeff(), 0.005);
  EXPECT_LT((mean_log - d.mean_log()).cwiseAbs().maxCoeff(), 0.05);
}

// --- sufficient statistics ----------------------------------------------------------------------

TEST(DirichletStats, MergeAndOneByOneEqualAllAtOnce) {
  const Dirichlet d(Eigen::Vector4d(0.3, 1.0, 2.0, 7.0));
  core::Rng rng(9);
  const Eigen::MatrixXd logs = d.sample_log(rng, 1000);
  const DirichletStats all = DirichletStats::of_log_proportions(logs);
  const DirichletStats first = DirichletStats::of_log_proportions(logs.topRows(300));
  DirichletStats merged = DirichletStats::of_log_proportions(logs.bottomRows(700));
  merged.merge(first);
  DirichletStats one_by_one;
  for (Eigen::Index i = 0; i < logs.rows(); ++i) one_by_one.add_log(logs.row(i).transpose());
  EXPECT_EQ(all.count(), 1000.0);
  EXPECT_EQ(merged.count(), 1000.0);
  EXPECT_EQ(one_by_one.count(), 1000.0);
  EXPECT_LT((merged.mean_log() - all.mean_log()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((one_by_one.mean_log() - all.mean_log()).cwiseAbs().maxCoeff(), 1e-12);
  // The same from proportions.
  const DirichletStats from_p = DirichletStats::of_proportions(logs.array().exp().matrix());
  EXPECT_LT((from_p.mean_log() - all.mean_log()).cwiseAbs().maxCoeff(), 1e-12);
  // Merging into and from empty statistics changes nothing.
  DirichletStats empty;
  empty.merge(all);
  EXPECT_EQ(empty.mean_log(), all.mean_log());
  DirichletStats again = all;
  again.merge(DirichletStats(4));
  EXPECT_EQ(again.mean_log(), all.mean_log());
  EXPECT_EQ(again.count(), all.count());
  // A sample of weight 2 is the sample twice.
  DirichletStats twice;
  twice.add_log(logs.row(0).transpose());
  twice.add_log(logs.row(0).transpose());
  twice.add_log(logs.row(1).transpose());
  DirichletStats weighted;
  weighted.add_log(logs.row(0).transpose(), 2.0);
  weighted.add_log(logs.row(1).transpose());
  EXPECT_LT((twice.mean_log() - weighted.mean_log()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(DirichletStats, ScalingForgetsOldSamples) {
  DirichletStats old_stats;
  old_stats.add_log(Eigen::Vector2d(std::log(0.5), std::log(0.5)), 10.0);
  DirichletStats fresh;
  fresh.add_log(Eigen::Vector2d(std::log(0.9), std::log(0.1)), 10.0);
  DirichletStats forgotten = old_stats;
  forgotten.scale(0.25);
  EXPECT_EQ(forgotten.count(), 2.5);
  EXPECT_EQ(forgotten.mean_log(), old_stats.mean_log());
  forgotten.merge(fresh);
  // 2.5 : 10, so the new samples weigh 0.8.
  EXPECT_NEAR(forgotten.mean_log()(1), 0.2 * std::log(0.5) + 0.8 * std::log(0.1), 1e-14);
  EXPECT_TRUE(has(error_of([&] { forgotten.scale(0.0); }), "factor"));
  EXPECT_TRUE(has(error_of([&] { forgotten.scale(1.5); }), "factor"));
}

TEST(DirichletStats, BadProportionsNameTheRow) {
  Eigen::MatrixXd p(4, 3);
  p << 0.2, 0.3, 0.5, 0.1, 0.1, 0.8, 0.3, 0.3, 0.4, 0.5, 0.25, 0.25;
  EXPECT_NO_THROW((void)DirichletStats::of_proportions(p));
  Eigen::MatrixXd negative = p;
  negative(2, 1) = -0.1;
  EXPECT_TRUE(
      has(error_of([&] { (void)DirichletStats::of_proportions(negative); }), "row 2: entry 1"));
  Eigen::MatrixXd nan = p;
  nan(3, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(has(error_of([&] { (void)DirichletStats::of_proportions(nan); }), "row 3"));
  Eigen::MatrixXd off = p;
  off(1, 2) = 0.7;  // sums to 0.9
  EXPECT_TRUE(
      has(error_of([&] { (void)DirichletStats::of_proportions(off); }), "row 1: sums to 0.9"));
  // Within the stated tolerance passes; beyond it fails.
  Eigen::MatrixXd close = p;
  close(0, 0) += 0.5 * kProportionSumTolerance;
  EXPECT_NO_THROW((void)DirichletStats::of_proportions(close));
  close(0, 0) += kProportionSumTolerance;
  EXPECT_TRUE(has(error_of([&] { (void)DirichletStats::of_proportions(close); }), "row 0"));
  // The fit reports the same.
  EXPECT_TRUE(has(error_of([&] { (void)fit_dirichlet(off); }), "row 1"));
  // Log-proportions: NaN, +inf, positive, rows not summing to 1, a row of -inf.
  const Eigen::MatrixXd logs = p.array().log();
  EXPECT_NO_THROW((void)DirichletStats::of_log_proportions(logs));
  Eigen::MatrixXd bad = logs;
  bad(2, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(has(error_of([&] { (void)DirichletStats::of_log_proportions(bad); }), "row 2"));
  bad = logs;
  bad(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(has(error_of([&] { (void)fit_dirichlet_log(bad); }), "row 1"));
  bad = logs;
  bad(3, 0) = std::log(0.4);
  EXPECT_TRUE(
      has(error_of([&] { (void)DirichletStats::of_log_proportions(bad); }), "row 3: logsumexp"));
  bad = logs;
  bad.row(0).setConstant(-std::numeric_limits<double>::infinity());
  EXPECT_TRUE(has(error_of([&] { (void)DirichletStats::of_log_proportions(bad); }), "row 0"));
  // add_log: wrong size, non-finite, bad weight.
  DirichletStats s(3);
  EXPECT_TRUE(has(error_of([&] { s.add_log(Eigen::Vector2d(-1.0, -1.0)); }), "size 2"));
  EXPECT_TRUE(has(error_of([&] {
                    s.add_log(
                        Eigen::Vector3d(-1.0, -std::numeric_limits<double>::infinity(), -1.0));
                  }),
                  "entry 1"));
  EXPECT_TRUE(has(error_of([&] { s.add_log(Eigen::Vector3d(-1.0, -1.0, -1.0), 0.0); }), "weight"));
  DirichletStats two(2);
  two.add_log(Eigen::Vector2d(std::log(0.5), std::log(0.5)));
  EXPECT_TRUE(has(error_of([&] { s.merge(two); }), "dimensions 3 and 2"));
}

TEST(DirichletStats, ZerosAreFlooredAndCounted) {
  Eigen::MatrixXd p(3, 3);
  p << 0.5, 0.5, 0.0, 0.2, 0.0, 0.8, 0.005, 0.295, 0.7;
  const DirichletStats s = DirichletStats::of_proportions(p);
  EXPECT_EQ(s.clamped(), 2);
  EXPECT_TRUE(s.mean_log().allFinite());
  EXPECT_NEAR(s.mean_log()(2), (std::log(kDirichletFloor) + std::log(0.8) + std::log(0.7)) / 3,
              1e-12);
  ProportionOptions o;
  o.floor = 0.01;
  EXPECT_EQ(DirichletStats::of_proportions(p, o).clamped(), 3);  // 0, 0, and 0.005
  const DirichletStats l = DirichletStats::of_log_proportions(p.array().log());
  EXPECT_EQ(l.clamped(), 2);
  EXPECT_LT((l.mean_log() - s.mean_log()).cwiseAbs().maxCoeff(), 1e-12);
  DirichletStats merged = s;
  merged.merge(l);
  EXPECT_EQ(merged.clamped(), 4);
}

// --- options ------------------------------------------------------------------------------------

TEST(DirichletFit, OptionValidationNamesTheOption) {
  const auto bad = [](auto change) {
    DirichletFitOptions o;
    change(o);
    return error_of([&] { o.validate(); });
  };
  EXPECT_NO_THROW(DirichletFitOptions{}.validate());
  EXPECT_TRUE(has(bad([](DirichletFitOptions& o) { o.tolerance = 0.0; }), "tolerance"));
  EXPECT_TRUE(has(
      bad([](DirichletFitOptions& o) { o.tolerance = std::numeric_limits<double>::quiet_NaN(); }),
      "tolerance"));
  EXPECT_TRUE(has(bad([](DirichletFitOptions& o) { o.max_iterations = 0; }), "max_iterations"));
  EXPECT_TRUE(
      has(bad([](DirichletFitOptions& o) { o.fixed_point_steps = 0; }), "fixed_point_steps"));
  EXPECT_TRUE(
      has(bad([](DirichletFitOptions& o) { o.fixed_point_steps = 1000; }), "fixed_point_steps"));
  EXPECT_TRUE(has(bad([](DirichletFitOptions& o) { o.max_precision = 0.5; }), "max_precision"));
  EXPECT_TRUE(has(bad([](DirichletFitOptions& o) { o.proportions.floor = 0.0; }), "floor"));
  EXPECT_TRUE(has(bad([](DirichletFitOptions& o) { o.proportions.floor = 0.5; }), "floor"));
  EXPECT_TRUE(has(bad([](DirichletFitOptions& o) { o.proportions.sum_tolerance = -1.0; }),
                  "sum_tolerance"));
  EXPECT_TRUE(has(error_of([] { (void)fit_dirichlet(DirichletStats(3)); }), "no samples"));
  DirichletStats far;
  far.add_log(Eigen::Vector2d(0.0, -1e200));
  EXPECT_TRUE(has(error_of([&] { (void)fit_dirichlet(far); }), "mean log-proportion 1"));
  DirichletStats one_dim;
  one_dim.add_log(Eigen::VectorXd::Zero(1));
  EXPECT_TRUE(has(error_of([&] { (void)fit_dirichlet(one_dim); }), "at least 2"));
}

// --- the fit ------------------------------------------------------------------------------------

// The correctness test: 1,000 random problems, T in [2, 25], alpha log-uniform in
// [1e-3, 1e3], 1,000 samples drawn in log space.
TEST(DirichletFit, RandomProblemsConvergeFastToTheMaximum) {
  core::Rng rng(2003);
  const DirichletFitOptions options;
  int worst_iterations = 0;
  int halvings = 0;
  int fallbacks = 0;
  constexpr int kProblems = 1000;
  for (int problem = 0; problem < kProblems; ++problem) {
    const int dim = 2 + static_cast<int>(rng.index(24));
    const Dirichlet truth(random_alpha(rng, dim, 1e-3, 1e3));
    const Eigen::MatrixXd logs = truth.sample_log(rng, 1000);
    const DirichletStats stats = DirichletStats::of_log_proportions(logs);
    const DirichletFit fit = fit_dirichlet(stats, options);
    const auto& s = fit.summary;
    SCOPED_TRACE("problem " + std::to_string(problem) + ": " + s.brief());
    ASSERT_TRUE(s.converged);
    ASSERT_TRUE(fit.dirichlet.alpha().allFinite());
    ASSERT_LE(s.iterations(), 20);
    ASSERT_LE(s.gradient_max_norm, options.tolerance * stats.count());
    const double truth_l = truth.log_likelihood(stats);
    ASSERT_GE(s.log_likelihood, truth_l - 1e-9 * std::max(1.0, std::abs(truth_l)));
    ASSERT_NEAR(fit.dirichlet.log_likelihood(stats), s.log_likelihood,
                1e-9 * std::max(1.0, std::abs(truth_l)));
    worst_iterations = std::max(worst_iterations, s.iterations());
    halvings += s.step_halvings;
    fallbacks += s.newton_fallbacks;
  }
  std::cout << "[          ] " << kProblems << " problems: at most " << worst_iterations
            << " iterations, " << halvings << " step halvings, " << fallbacks << " fallbacks\n";
}

// The standard error of each alpha_k from n samples: the square roots of the diagonal of the
// inverse Fisher information n (diag(psi'(alpha)) - psi'(s) 1 1^T) (minus Minka's Hessian).
Eigen::VectorXd standard_errors(const Eigen::VectorXd& alpha, double n) {
  const auto dim = alpha.size();
  Eigen::MatrixXd info = Eigen::MatrixXd::Constant(dim, dim, -detail::trigamma(alpha.sum()));
  for (Eigen::Index k = 0; k < dim; ++k) info(k, k) += detail::trigamma(alpha(k));
  info *= n;
  return info.inverse().diagonal().cwiseSqrt();
}

// "Within 5%" is a statistical claim: with 10,000 samples it holds only where 5% is several
// standard errors (it is 3.9 for Dir(0.5, 0.5), and about 1.2 for alpha_2 of Dir(0.05, 4.5)).
// Each known alpha here is checked to have 5% >= 3 standard errors in every component (random
// ones that do not are drawn again, and counted), so that the 5% check tests the fit and not luck.
bool determinable(const Eigen::VectorXd& alpha, double n) {
  return (3.0 * standard_errors(alpha, n).array() <= 0.05 * alpha.array()).all();
}

std::vector<Eigen::VectorXd> known_alphas(core::Rng& rng, double lo, double hi, int random,
                                          int& rejected) {
  std::vector<Eigen::VectorXd> alphas = {
      Eigen::Vector2d(0.5, 0.5),
      (Eigen::VectorXd(6) << 1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0).finished(),
      Eigen::Vector4d(2.0, 10.0, 50.0, 1e3)};
  alphas.erase(std::remove_if(alphas.begin(), alphas.end(),
                              [&](const Eigen::VectorXd& a) { return a.minCoeff() < lo; }),
               alphas.end());
  for (const auto& a : alphas) EXPECT_TRUE(determinable(a, 10000)) << a.transpose();
  rejected = 0;
  for (int i = 0; i < random;) {
    const int dim = 2 + static_cast<int>(rng.index(24));
    Eigen::VectorXd a = random_alpha(rng, dim, lo, hi);
    a(0) = lo;  // the hardest: the smallest alpha, the most mass near 0
    if (!determinable(a, 10000)) {
      ++rejected;
      continue;
    }
    alphas.push_back(a);
    ++i;
  }
  return alphas;
}

TEST(DirichletFit, TenThousandSamplesGiveAlphaBackWithinFivePercent) {
  core::Rng rng(77);
  int rejected = 0;
  const auto alphas = known_alphas(rng, 1e-3, 1e3, 12, rejected);
  for (const auto& alpha : alphas) {
    const Dirichlet truth(alpha);
    const DirichletFit fit = fit_dirichlet_log(truth.sample_log(rng, 10000));
    SCOPED_TRACE(fit.summary.brief());
    EXPECT_TRUE(fit.summary.converged);
    EXPECT_EQ(fit.summary.clamped, 0);
    EXPECT_LT(max_relative_error(fit.dirichlet.alpha(), alpha), 0.05)
        << fit.dirichlet.alpha().transpose() << " vs " << alpha.transpose();
  }
  std::cout << "[          ] " << alphas.size() << " alphas (" << rejected
            << " random ones drawn again: 5% below 3 standard errors)\n";
}

// Proportions rather than log-proportions, alpha in [0.05, 1e3]: (a) double proportions at the
// default floor; (b) proportions rounded to single precision (underflow to 0 below ~1e-45, as in
// a float E-step) at floor 1e-38: the floor is hit and counted, and alpha still comes back.
TEST(DirichletFit, FlooredProportionsGiveAlphaBackWithinFivePercent) {
  core::Rng rng(4);
  int rejected = 0;
  const auto alphas = known_alphas(rng, 0.05, 1e3, 12, rejected);
  std::int64_t clamped = 0;
  for (const auto& alpha : alphas) {
    const Dirichlet truth(alpha);
    const Eigen::MatrixXd p = truth.sample_log(rng, 10000).array().exp();
    const DirichletFit fit = fit_dirichlet(p);
    EXPECT_TRUE(fit.summary.converged) << fit.summary.brief();
    EXPECT_LT(max_relative_error(fit.dirichlet.alpha(), alpha), 0.05) << fit.summary.brief();

    const Eigen::MatrixXd single = p.cast<float>().cast<double>();
    DirichletFitOptions o;
    o.proportions.floor = 1e-38;
    const DirichletFit fit32 = fit_dirichlet(single, o);
    EXPECT_TRUE(fit32.summary.converged) << fit32.summary.brief();
    EXPECT_LT(max_relative_error(fit32.dirichlet.alpha(), alpha), 0.05)
        << fit32.summary.brief() << "\n"
        << fit32.dirichlet.alpha().transpose() << " vs " << alpha.transpose();
    clamped += fit32.summary.clamped;
  }
  EXPECT_GT(clamped, 0);  // the test did exercise the floor
  std::cout << "[          ] " << alphas.size() << " alphas (" << rejected
            << " random ones drawn again), " << clamped << " single-precision zeros floored\n";
}

void expect_finite(const DirichletFit& fit) {
  EXPECT_TRUE(fit.dirichlet.alpha().allFinite());
  EXPECT_GT(fit.dirichlet.alpha().minCoeff(), 0.0);
  EXPECT_TRUE(std::isfinite(fit.summary.log_likelihood));
  EXPECT_TRUE(std::isfinite(fit.summary.gradient_max_norm));
  EXPECT_FALSE(fit.summary.message.empty());
}

TEST(DirichletFit, ExactZerosAreFlooredAndReported) {
  core::Rng rng(11);
  const Dirichlet truth(Eigen::Vector4d(0.5, 2.0, 1.0, 3.0));
  Eigen::MatrixXd p = truth.sample_log(rng, 500).array().exp();
  // Some zeros scattered, renormalising their rows; and one component zero in every sample.
  for (int i = 0; i < 500; i += 7) p(i, 1) = 0.0;
  p.col(3).setZero();
  for (Eigen::Index i = 0; i < p.rows(); ++i) p.row(i) /= p.row(i).sum();
  const DirichletFit fit = fit_dirichlet(p);
  SCOPED_TRACE(fit.summary.brief());
  expect_finite(fit);
  EXPECT_TRUE(fit.summary.converged);
  EXPECT_EQ(fit.summary.clamped, 500 + 72);
  EXPECT_TRUE(has(fit.summary.brief(), "572 proportions clamped"));
  // The always-zero component gets a tiny alpha: ~1 / 690, psi^-1 of log(floor) and more.
  EXPECT_LT(fit.dirichlet.alpha()(3), 0.01);
}

TEST(DirichletFit, AConstantComponentGivesAFiniteFit) {
  core::Rng rng(12);
  const Dirichlet rest(Eigen::Vector3d(1.0, 2.0, 3.0));
  Eigen::MatrixXd p(400, 4);
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    p(i, 0) = 0.25;
    p.row(i).tail(3) = 0.75 * rest.sample(rng).transpose();
  }
  const DirichletFit fit = fit_dirichlet(p);
  SCOPED_TRACE(fit.summary.brief());
  expect_finite(fit);
  EXPECT_TRUE(fit.summary.converged);
  // The mean of the constant component is right.
  EXPECT_NEAR(fit.dirichlet.mean()(0), 0.25, 0.05);
  // With two components, a constant one makes every sample the same point: the precision bound.
  Eigen::MatrixXd two(50, 2);
  two.col(0).setConstant(0.3);
  two.col(1).setConstant(0.7);
  const DirichletFit bound = fit_dirichlet(two);
  expect_finite(bound);
  EXPECT_EQ(bound.summary.stop, DirichletStop::kPrecisionBound);
  EXPECT_FALSE(bound.summary.converged);
}

TEST(DirichletFit, OneSampleAndDuplicateRowsHitThePrecisionBound) {
  const Eigen::RowVector4d row(0.1, 0.2, 0.3, 0.4);
  const DirichletFitOptions options;
  for (const int n : {1, 2, 100}) {
    const Eigen::MatrixXd p = row.replicate(n, 1);
    const DirichletFit fit = fit_dirichlet(p, options);
    SCOPED_TRACE(fit.summary.brief());
    expect_finite(fit);
    EXPECT_EQ(fit.summary.stop, DirichletStop::kPrecisionBound);
    EXPECT_TRUE(has(fit.summary.message, "max_precision"));
    EXPECT_NEAR(fit.dirichlet.precision(), options.max_precision, 1e-6 * options.max_precision);
    EXPECT_LT(max_relative_error(fit.dirichlet.mean(), row.transpose()), 1e-6);
  }
  // One sample with a zero in it.
  const DirichletFit zero = fit_dirichlet(Eigen::RowVector3d(0.0, 0.5, 0.5));
  expect_finite(zero);
  EXPECT_EQ(zero.summary.clamped, 1);
  // Two distinct rows, each many times: a proper maximum.
  Eigen::MatrixXd two(200, 3);
  for (Eigen::Index i = 0; i < 200; ++i) {
    two.row(i) = i % 2 ? Eigen::RowVector3d(0.2, 0.3, 0.5) : Eigen::RowVector3d(0.4, 0.4, 0.2);
  }
  const DirichletFit fit = fit_dirichlet(two);
  SCOPED_TRACE(fit.summary.brief());
  expect_finite(fit);
  EXPECT_TRUE(fit.summary.converged);
}

TEST(DirichletFit, SummaryCountsTheIterationsItTook) {
  core::Rng rng(21);
  const Dirichlet truth(Eigen::Vector3d(0.3, 3.0, 30.0));
  const DirichletStats stats = DirichletStats::of_log_proportions(truth.sample_log(rng, 2000));
  DirichletFitOptions o;
  o.max_iterations = 2;
  o.fixed_point_steps = 2;
  const DirichletFit capped = fit_dirichlet(stats, o);
  EXPECT_EQ(capped.summary.stop, DirichletStop::kMaxIterations);
  EXPECT_EQ(capped.summary.iterations(), 2);
  EXPECT_TRUE(has(capped.summary.message, "max_iterations = 2"));
  EXPECT_TRUE(has(capped.summary.brief(), "max-iterations after 2 fixed-point + 0 Newton"));
  // Fixed point alone converges too, only more slowly than with Newton.
  o.max_iterations = 10000;
  o.fixed_point_steps = 10000;
  const DirichletFit slow = fit_dirichlet(stats, o);
  const DirichletFit fast = fit_dirichlet(stats);
  EXPECT_TRUE(slow.summary.converged);
  EXPECT_EQ(slow.summary.newton_iterations, 0);
  EXPECT_TRUE(fast.summary.converged);
  EXPECT_GT(fast.summary.newton_iterations, 0);
  EXPECT_LT(fast.summary.iterations(), slow.summary.iterations());
  EXPECT_LT(max_relative_error(slow.dirichlet.alpha(), fast.dirichlet.alpha()), 1e-6);
}

}  // namespace
}  // namespace proprio::topics
