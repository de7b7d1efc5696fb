// Mixtures of Dirichlets (EM with the Minka fit as M-step, components by BIC) and Dirichlets with
// one shared precision: known answers on data drawn from known models.
#include "proprio/topics/dirichlet_mixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"

namespace proprio::topics {
namespace {

/// n rows of log-proportions from w1 Dir(a) + (1 - w1) Dir(b).
Eigen::MatrixXd draw_mixture(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double w1, int n,
                             std::uint64_t seed) {
  core::Rng rng(seed);
  const Dirichlet da(a);
  const Dirichlet db(b);
  Eigen::MatrixXd out(n, a.size());
  for (int i = 0; i < n; ++i) {
    out.row(i) = (rng.uniform() < w1 ? da : db).sample_log(rng).transpose();
  }
  return out;
}

double max_relative_error(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
  return ((got - want).array().abs() / want.array()).maxCoeff();
}

TEST(DirichletMixture, RecoversAKnownTwoComponentMixture) {
  Eigen::VectorXd a(4), b(4);
  a << 8.0, 1.0, 0.5, 0.5;
  b << 0.5, 0.5, 2.0, 6.0;
  const Eigen::MatrixXd x = draw_mixture(a, b, 0.3, 4000, 11);
  DirichletMixtureOptions o;
  o.max_components = 4;
  const DirichletMixtureFit f = fit_dirichlet_mixture(x, o);
  ASSERT_EQ(f.mixture.num_components(), 2) << f.summary.brief();
  EXPECT_EQ(f.summary.bic.size(), 4U);
  EXPECT_EQ(f.summary.stop, MixtureStop::kConverged) << f.summary.brief();
  // Components in either order: the one with the larger alpha_0 is a.
  const bool first_is_a =
      f.mixture.components[0].dirichlet.alpha()(0) > f.mixture.components[1].dirichlet.alpha()(0);
  const auto& ca = f.mixture.components[first_is_a ? 0 : 1];
  const auto& cb = f.mixture.components[first_is_a ? 1 : 0];
  EXPECT_NEAR(ca.weight, 0.3, 0.03);
  EXPECT_NEAR(cb.weight, 0.7, 0.03);
  EXPECT_LT(max_relative_error(ca.dirichlet.alpha(), a), 0.1) << ca.dirichlet.alpha().transpose();
  EXPECT_LT(max_relative_error(cb.dirichlet.alpha(), b), 0.1) << cb.dirichlet.alpha().transpose();
  // The mixture explains the data better than one Dirichlet, per BIC too.
  EXPECT_LT(f.summary.bic[1], f.summary.bic[0]);
  EXPECT_NO_THROW(f.mixture.validate());
}

TEST(DirichletMixture, OneDirichletGivesOneComponent) {
  Eigen::VectorXd a(3);
  a << 2.0, 3.0, 5.0;
  const Eigen::MatrixXd x = draw_mixture(a, a, 1.0, 600, 3);
  DirichletMixtureOptions o;
  o.max_components = 3;
  const DirichletMixtureFit f = fit_dirichlet_mixture(x, o);
  EXPECT_EQ(f.mixture.num_components(), 1) << f.summary.brief();
  EXPECT_EQ(f.summary.stop, MixtureStop::kOneComponent);
}

TEST(DirichletMixture, OneComponentIsExactlyThePlainFit) {
  Eigen::VectorXd a(5);
  a << 0.2, 0.5, 1.0, 3.0, 0.1;
  const Eigen::MatrixXd x = draw_mixture(a, a, 1.0, 300, 5);
  const DirichletMixtureFit f = fit_dirichlet_mixture_k(x, 1);
  DirichletStats s(5);
  for (Eigen::Index i = 0; i < x.rows(); ++i) s.add_log(x.row(i).transpose());
  const DirichletFit plain = fit_dirichlet(s);
  ASSERT_EQ(f.mixture.num_components(), 1);
  EXPECT_EQ(f.mixture.components[0].weight, 1.0);
  // Bitwise: the same statistics and the same fit.
  EXPECT_EQ(f.mixture.components[0].dirichlet.alpha(), plain.dirichlet.alpha());
  EXPECT_EQ(f.summary.log_likelihood, plain.summary.log_likelihood);
  const Eigen::VectorXd p = x.row(7).transpose();
  EXPECT_EQ(f.mixture.log_density_of_log(p), plain.dirichlet.log_density_of_log(p));
}

TEST(DirichletMixture, SeededAndDeterministic) {
  Eigen::VectorXd a(3), b(3);
  a << 5.0, 1.0, 1.0;
  b << 1.0, 1.0, 5.0;
  const Eigen::MatrixXd x = draw_mixture(a, b, 0.5, 500, 9);
  DirichletMixtureOptions o;
  o.max_components = 3;
  const DirichletMixtureFit f1 = fit_dirichlet_mixture(x, o);
  const DirichletMixtureFit f2 = fit_dirichlet_mixture(x, o);
  ASSERT_EQ(f1.mixture.num_components(), f2.mixture.num_components());
  for (int j = 0; j < f1.mixture.num_components(); ++j) {
    EXPECT_EQ(f1.mixture.components[static_cast<std::size_t>(j)].dirichlet.alpha(),
              f2.mixture.components[static_cast<std::size_t>(j)].dirichlet.alpha());
  }
  EXPECT_EQ(f1.summary.log_likelihood, f2.summary.log_likelihood);
}

TEST(DirichletMixture, DegenerateStartsAreDiscardedAndTooFewSamplesAreAnError) {
  Eigen::VectorXd a(3);
  a << 1.0, 2.0, 3.0;
  const Eigen::MatrixXd x = draw_mixture(a, a, 1.0, 12, 2);
  DirichletMixtureOptions o;
  o.min_component_count = 10;
  // 12 samples cannot give 2 components of 10 each: only K = 1 is tried.
  EXPECT_EQ(fit_dirichlet_mixture(x, o).summary.bic.size(), 1U);
  EXPECT_THROW((void)fit_dirichlet_mixture_k(x, 2, o), Error);
  EXPECT_THROW((void)fit_dirichlet_mixture_k(x.topRows(1), 1, o), Error);
  o.min_component_count = 1;
  EXPECT_THROW(o.validate(), Error);
}

TEST(DirichletSharedPrecision, RecoversOnePrecisionAndTheMeans) {
  // Three classes of one precision 12 and different means.
  std::vector<Eigen::VectorXd> means(3, Eigen::VectorXd(4));
  means[0] << 0.7, 0.1, 0.1, 0.1;
  means[1] << 0.1, 0.6, 0.2, 0.1;
  means[2] << 0.25, 0.25, 0.25, 0.25;
  core::Rng rng(21);
  std::vector<DirichletStats> stats;
  for (const auto& m : means) {
    const Dirichlet d(12.0 * m);
    DirichletStats s(4);
    for (int i = 0; i < 3000; ++i) s.add_log(d.sample_log(rng));
    stats.push_back(s);
  }
  const SharedPrecisionFit f = fit_dirichlets_shared_precision(stats);
  EXPECT_TRUE(f.summary.converged) << f.summary.brief();
  EXPECT_NEAR(f.summary.precision, 12.0, 0.6);
  ASSERT_EQ(f.dirichlets.size(), 3U);
  double independent = 0;
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(f.dirichlets[c].precision(), f.summary.precision, 1e-9 * f.summary.precision);
    EXPECT_LT((f.dirichlets[c].mean() - means[c]).cwiseAbs().maxCoeff(), 0.01);
    independent += fit_dirichlet(stats[c]).summary.log_likelihood;
  }
  // A constrained maximum: no better than the independent fits, and close to them here.
  EXPECT_LE(f.summary.log_likelihood, independent + 1e-6 * std::abs(independent));
  EXPECT_GT(f.summary.log_likelihood, independent - 20.0);
}

TEST(DirichletSharedPrecision, OneClassIsTheIndependentFit) {
  Eigen::VectorXd a(3);
  a << 0.4, 2.0, 1.5;
  core::Rng rng(4);
  const Dirichlet d(a);
  DirichletStats s(3);
  for (int i = 0; i < 2000; ++i) s.add_log(d.sample_log(rng));
  const SharedPrecisionFit f = fit_dirichlets_shared_precision({s});
  const Dirichlet plain = fit_dirichlet(s).dirichlet;
  EXPECT_LT(max_relative_error(f.dirichlets[0].alpha(), plain.alpha()), 1e-6);
  EXPECT_THROW((void)fit_dirichlets_shared_precision({}), Error);
}

}  // namespace
}  // namespace proprio::topics
