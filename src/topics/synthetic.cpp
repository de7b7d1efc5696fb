#include "proprio/topics/synthetic.hpp"

#include <cmath>
#include <vector>

#include "gamma_variate.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"

namespace proprio::topics {

namespace {

// Gamma(shape, 1) by Marsaglia & Tsang, with the shape < 1 boost u^(1/shape).
double gamma_variate(core::Rng& rng, double shape) {
  if (shape < 1.0) return gamma_variate(rng, shape + 1.0) * std::pow(rng.uniform(), 1.0 / shape);
  const detail::GammaFactors g = detail::marsaglia_tsang(rng, shape);
  return g.d * g.v;
}

Eigen::VectorXd dirichlet(core::Rng& rng, int n, double a) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = std::max(gamma_variate(rng, a), 1e-300);
  return v / v.sum();
}

int poisson(core::Rng& rng, double mean) {
  if (mean > 30)
    return std::max(0, static_cast<int>(std::lround(rng.normal(mean, std::sqrt(mean)))));
  const double l = std::exp(-mean);
  int k = 0;
  double p = rng.uniform();
  while (p > l) {
    ++k;
    p *= rng.uniform();
  }
  return k;
}

// Index drawn from the cumulative distribution `cdf` (last entry 1).
int draw(core::Rng& rng, const std::vector<double>& cdf) {
  const double u = rng.uniform() * cdf.back();
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
  return static_cast<int>(
      std::min<std::ptrdiff_t>(it - cdf.begin(), static_cast<std::ptrdiff_t>(cdf.size()) - 1));
}

}  // namespace

void SyntheticCorpusOptions::validate() const {
  if (num_topics < 1 || num_words < 1 || num_documents < 0) {
    throw Error("synthetic corpus: topics and words must be at least 1, documents >= 0");
  }
  if (!(mean_length > 0 && std::isfinite(mean_length))) {
    throw Error("synthetic corpus: mean_length must be positive");
  }
  if (!(alpha > 0 && eta > 0)) throw Error("synthetic corpus: alpha and eta must be positive");
}

SyntheticCorpus make_synthetic_corpus(const SyntheticCorpusOptions& o) {
  o.validate();
  core::Rng rng(o.seed);
  SyntheticCorpus s;
  s.topics.resize(o.num_topics, o.num_words);
  std::vector<std::vector<double>> cdf(static_cast<std::size_t>(o.num_topics));
  for (int k = 0; k < o.num_topics; ++k) {
    s.topics.row(k) = dirichlet(rng, o.num_words, o.eta).transpose();
    auto& c = cdf[static_cast<std::size_t>(k)];
    c.resize(static_cast<std::size_t>(o.num_words));
    double acc = 0;
    for (int w = 0; w < o.num_words; ++w) c[static_cast<std::size_t>(w)] = acc += s.topics(k, w);
  }
  s.corpus = Corpus(o.num_words);
  s.theta.resize(o.num_documents, o.num_topics);
  std::vector<double> tcdf(static_cast<std::size_t>(o.num_topics));
  std::vector<std::int32_t> tokens;
  for (int d = 0; d < o.num_documents; ++d) {
    const Eigen::VectorXd theta = dirichlet(rng, o.num_topics, o.alpha);
    s.theta.row(d) = theta.transpose();
    double acc = 0;
    for (int k = 0; k < o.num_topics; ++k) tcdf[static_cast<std::size_t>(k)] = acc += theta(k);
    const int n = std::max(1, poisson(rng, o.mean_length));
    tokens.clear();
    for (int i = 0; i < n; ++i) {
      const int z = draw(rng, tcdf);
      tokens.push_back(draw(rng, cdf[static_cast<std::size_t>(z)]));
    }
    s.corpus.add_tokens(tokens);
  }
  return s;
}

}  // namespace proprio::topics
