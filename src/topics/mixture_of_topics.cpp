#include "proprio/topics/mixture_of_topics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"

#include "kmeans_seeding.hpp"
#include "special_functions.hpp"

namespace proprio::topics {
namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

double log_sum_exp(const Eigen::Ref<const Eigen::VectorXd>& x) {
  const double m = x.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((x.array() - m).exp().sum());
}

/// Minimum number of views of an object: one view does not determine a Dirichlet's precision.
constexpr int kMinViews = 2;

/// Statistics of the rows of log_theta whose label is c.
DirichletStats stats_of(const Eigen::MatrixXd& log_theta, std::span<const int> labels, int c) {
  DirichletStats s(static_cast<int>(log_theta.cols()));
  for (Eigen::Index d = 0; d < log_theta.rows(); ++d) {
    if (labels[static_cast<std::size_t>(d)] == c) s.add_log(log_theta.row(d).transpose());
  }
  return s;
}

/// The mixture options of MotOptions.
DirichletMixtureOptions mixture_options(const MotOptions& o, std::uint64_t object) {
  DirichletMixtureOptions m;
  m.max_components = o.components;
  m.restarts = o.component_restarts;
  m.max_iterations = o.component_iterations;
  m.min_component_count = o.component_min_views;
  m.seed = core::stream_seed(o.seed, 0x4d495854ULL, object);  // "MIXT", the object's index
  m.fit = o.fit;
  return m;
}

/// Every object's Dirichlet refitted with one shared precision (MotOptions::shared_precision).
SharedPrecisionSummary share_precision(MotModel& model, const MotOptions& options) {
  std::vector<DirichletStats> stats;
  stats.reserve(model.objects.size());
  for (const auto& o : model.objects) stats.push_back(o.stats);
  SharedPrecisionFit f = fit_dirichlets_shared_precision(stats, options.fit);
  for (std::size_t c = 0; c < model.objects.size(); ++c) {
    model.objects[c].dirichlet = std::move(f.dirichlets[c]);
  }
  return f.summary;
}

/// The mixture of an object's views (log theta rows), kept only when BIC chose more than one
/// component (an empty mixture otherwise: `dirichlet` is the same fit).
DirichletMixture object_mixture(const Eigen::MatrixXd& rows, const MotOptions& options,
                                std::uint64_t object, DirichletMixtureSummary& summary) {
  DirichletMixtureFit f = fit_dirichlet_mixture(rows, mixture_options(options, object));
  summary = f.summary;
  if (f.mixture.num_components() < 2) return {};
  return std::move(f.mixture);
}

/// The rows of log_theta whose label is c.
Eigen::MatrixXd rows_of(const Eigen::MatrixXd& log_theta, std::span<const int> labels, int c) {
  std::vector<Eigen::Index> idx;
  for (Eigen::Index d = 0; d < log_theta.rows(); ++d) {
    if (labels[static_cast<std::size_t>(d)] == c) idx.push_back(d);
  }
  Eigen::MatrixXd out(static_cast<Eigen::Index>(idx.size()), log_theta.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) {
    out.row(static_cast<Eigen::Index>(i)) = log_theta.row(idx[i]);
  }
  return out;
}

/// The model fitted to log_theta by labels in [0, C) (-1 ignored); every class has >= 2 views.
/// `supervised`: MotOptions::components and shared_precision apply.
MotFit fit_labelled(const Eigen::MatrixXd& log_theta, std::span<const int> labels,
                    const std::vector<std::string>& classes, const MotOptions& options,
                    bool supervised = false) {
  MotFit out;
  out.model.prior = options.prior;
  out.model.smoothing = options.smoothing;
  out.summary.topics = static_cast<int>(log_theta.cols());
  out.summary.classes = static_cast<int>(classes.size());
  for (int c = 0; c < static_cast<int>(classes.size()); ++c) {
    DirichletStats s = stats_of(log_theta, labels, c);
    DirichletFit f = fit_dirichlet(s, options.fit);
    out.summary.fits.push_back(f.summary);
    const double views = s.count();
    out.model.objects.push_back(MotObject{classes[static_cast<std::size_t>(c)], std::move(s),
                                          std::move(f.dirichlet), views});
  }
  if (supervised && options.shared_precision) {
    out.summary.shared = share_precision(out.model, options);
  }
  if (supervised && options.components > 1) {
    for (int c = 0; c < static_cast<int>(classes.size()); ++c) {
      DirichletMixtureSummary m;
      out.model.objects[static_cast<std::size_t>(c)].mixture =
          object_mixture(rows_of(log_theta, labels, c), options, static_cast<std::uint64_t>(c), m);
      out.summary.mixtures.push_back(std::move(m));
    }
  }
  out.assignment.assign(labels.begin(), labels.end());
  for (const int l : labels) out.summary.views += l >= 0 ? 1 : 0;
  return out;
}

/// log Dir(theta_d | omega_c) + log p(c), D x C.
Eigen::MatrixXd log_scores(const MotModel& model, const Eigen::MatrixXd& log_theta) {
  const Eigen::VectorXd prior = model.log_prior();
  Eigen::MatrixXd out(log_theta.rows(), model.num_classes());
  for (Eigen::Index d = 0; d < log_theta.rows(); ++d) {
    for (int c = 0; c < model.num_classes(); ++c) {
      out(d, c) = model.objects[static_cast<std::size_t>(c)].log_density_of_log(
                      log_theta.row(d).transpose()) +
                  prior(c);
    }
  }
  return out;
}

double mixture_log_likelihood(const Eigen::MatrixXd& scores) {
  double l = 0;
  for (Eigen::Index d = 0; d < scores.rows(); ++d) l += log_sum_exp(scores.row(d).transpose());
  return l;
}

std::vector<int> argmax_rows(const Eigen::MatrixXd& m) {
  std::vector<int> out(static_cast<std::size_t>(m.rows()));
  for (Eigen::Index d = 0; d < m.rows(); ++d) {
    Eigen::Index best = 0;
    m.row(d).maxCoeff(&best);
    out[static_cast<std::size_t>(d)] = static_cast<int>(best);
  }
  return out;
}

std::vector<int> cluster_sizes(const std::vector<int>& assignment, int k) {
  std::vector<int> n(static_cast<std::size_t>(k), 0);
  for (const int a : assignment) ++n[static_cast<std::size_t>(a)];
  return n;
}

struct Clustering {
  std::vector<int> assignment;
  double sse = std::numeric_limits<double>::infinity();
};

/// One k-means++ start followed by Lloyd iterations over the rows of x.
Clustering kmeans_once(const Eigen::MatrixXd& x, int k, int iterations, core::Rng& rng) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd centres = detail::kmeans_pp_seeds(x, k, rng);
  Clustering out;
  out.assignment.assign(static_cast<std::size_t>(n), -1);
  for (int it = 0; it < iterations; ++it) {
    bool moved = false;
    double sse = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index best = 0;
      const double dist = (centres.rowwise() - x.row(i)).rowwise().squaredNorm().minCoeff(&best);
      sse += dist;
      auto& a = out.assignment[static_cast<std::size_t>(i)];
      if (a != static_cast<int>(best)) {
        a = static_cast<int>(best);
        moved = true;
      }
    }
    out.sse = sse;
    if (!moved) break;
    centres.setZero();
    std::vector<int> count(static_cast<std::size_t>(k), 0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const int a = out.assignment[static_cast<std::size_t>(i)];
      centres.row(a) += x.row(i);
      ++count[static_cast<std::size_t>(a)];
    }
    for (int j = 0; j < k; ++j) {
      if (count[static_cast<std::size_t>(j)] > 0) {
        centres.row(j) /= count[static_cast<std::size_t>(j)];
      } else {
        // An empty cluster restarts at the point farthest from its centre.
        Eigen::Index far = 0;
        Eigen::VectorXd dist(n);
        for (Eigen::Index i = 0; i < n; ++i) {
          dist(i) =
              (x.row(i) - centres.row(out.assignment[static_cast<std::size_t>(i)])).squaredNorm();
        }
        dist.maxCoeff(&far);
        centres.row(j) = x.row(far);
        out.assignment[static_cast<std::size_t>(far)] = j;
      }
    }
  }
  return out;
}

std::vector<std::string> object_names(int k) {
  std::vector<std::string> names;
  for (int c = 1; c <= k; ++c) names.push_back("object_" + std::to_string(c));
  return names;
}

/// The unsupervised fit with k objects; seed fixed per k so that results do not depend on which
/// other k were tried.
MotFit fit_clusters(const Eigen::MatrixXd& theta, const Eigen::MatrixXd& log_theta, int k,
                    const MotOptions& options) {
  auto rng = core::Rng::stream(options.seed, static_cast<std::uint64_t>(k));
  Clustering best;
  for (int r = 0; r < options.kmeans_restarts; ++r) {
    Clustering c = kmeans_once(theta, k, options.kmeans_iterations, rng);
    const auto sizes = cluster_sizes(c.assignment, k);
    if (*std::min_element(sizes.begin(), sizes.end()) < kMinViews) continue;
    if (c.sse < best.sse) best = std::move(c);
  }
  if (best.assignment.empty()) {
    throw Error("Mixture of Topics: no k-means start over " + std::to_string(theta.rows()) +
                " views gave each of " + std::to_string(k) +
                " objects at least 2 views; ask for fewer objects");
  }
  const auto names = object_names(k);
  MotFit fit = fit_labelled(log_theta, best.assignment, names, options);
  fit.summary.kmeans_sse = best.sse;
  for (int round = 0; round < options.refine_iterations && k > 1; ++round) {
    const std::vector<int> next = argmax_rows(log_scores(fit.model, log_theta));
    if (next == fit.assignment) break;
    const auto sizes = cluster_sizes(next, k);
    if (*std::min_element(sizes.begin(), sizes.end()) < kMinViews) break;
    MotFit refit = fit_labelled(log_theta, next, names, options);
    refit.summary.kmeans_sse = fit.summary.kmeans_sse;
    refit.summary.refine_rounds = round + 1;
    fit = std::move(refit);
  }
  fit.summary.log_likelihood = mixture_log_likelihood(log_scores(fit.model, log_theta));
  fit.summary.message = core::first_line(fit.summary.brief());
  return fit;
}

/// The exact rule for an object with a mixture: each new view (rows idx of log_theta) is merged
/// into every component's statistics with its responsibility under the old mixture (after the old
/// counts are multiplied by options.forgetting), each component is refitted and the weights are
/// the merged counts' shares: one step of online EM.
DirichletMixtureSummary update_mixture_exact(DirichletMixture& mixture,
                                             const Eigen::MatrixXd& log_theta,
                                             const std::vector<Eigen::Index>& idx,
                                             const MotOptions& options) {
  const int k = mixture.num_components();
  std::vector<DirichletStats> fresh(static_cast<std::size_t>(k),
                                    DirichletStats(static_cast<int>(log_theta.cols())));
  Eigen::VectorXd l(k);
  for (const Eigen::Index d : idx) {
    for (int j = 0; j < k; ++j) {
      const auto& c = mixture.components[static_cast<std::size_t>(j)];
      l(j) = std::log(c.weight) + c.dirichlet.log_density_of_log(log_theta.row(d).transpose());
    }
    const double z = log_sum_exp(l);
    for (int j = 0; j < k; ++j) {
      const double r = std::exp(l(j) - z);
      if (r > 0.0) fresh[static_cast<std::size_t>(j)].add_log(log_theta.row(d).transpose(), r);
    }
  }
  DirichletMixtureSummary summary;
  summary.samples = static_cast<int>(idx.size());
  summary.components = k;
  summary.iterations = 1;
  summary.stop = MixtureStop::kMaxIterations;
  double total = 0;
  for (int j = 0; j < k; ++j) {
    auto& c = mixture.components[static_cast<std::size_t>(j)];
    if (options.forgetting < 1.0) c.stats.scale(options.forgetting);
    c.stats.merge(fresh[static_cast<std::size_t>(j)]);
    DirichletFit f = fit_dirichlet(c.stats, options.fit);
    c.dirichlet = std::move(f.dirichlet);
    summary.log_likelihood += f.summary.log_likelihood;
    total += c.stats.count();
  }
  for (auto& c : mixture.components) c.weight = c.stats.count() / total;
  summary.message = core::first_line(summary.brief());
  return summary;
}

}  // namespace

void MotOptions::validate() const {
  core::check_field_bounds(*this, "Mixture of Topics");
  require(!(shared_precision && components > 1),
          "Mixture of Topics: shared_precision is for one Dirichlet per object, not with "
          "components > 1");
  fit.validate();
}

double MotObject::log_density_of_log(const Eigen::Ref<const Eigen::VectorXd>& log_theta) const {
  if (!mixture.components.empty()) return mixture.log_density_of_log(log_theta);
  return dirichlet.log_density_of_log(log_theta);
}

Eigen::VectorXd MotModel::log_prior() const {
  const int c = num_classes();
  Eigen::VectorXd out(c);
  if (prior == MotPrior::kUniform) {
    out.setConstant(-std::log(static_cast<double>(c)));
    return out;
  }
  double total = 0;
  for (const auto& o : objects) total += o.views;
  for (int i = 0; i < c; ++i) out(i) = std::log(objects[static_cast<std::size_t>(i)].views / total);
  return out;
}

std::vector<std::string> MotModel::names() const {
  std::vector<std::string> out;
  out.reserve(objects.size());
  for (const auto& o : objects) out.push_back(o.name);
  return out;
}

void MotModel::validate() const {
  require(!objects.empty(), "Mixture of Topics model: no objects");
  const int t = num_topics();
  require(t >= 2, "Mixture of Topics model: fewer than 2 topics");
  for (const auto& o : objects) {
    require(o.dirichlet.dim() == t,
            "Mixture of Topics model: object '" + o.name + "' has another number of topics");
    require(std::isfinite(o.views) && o.views > 0,
            "Mixture of Topics model: object '" + o.name + "' has no views");
    if (!o.mixture.components.empty()) {
      o.mixture.validate();
      require(o.mixture.components[0].dirichlet.dim() == t,
              "Mixture of Topics model: object '" + o.name +
                  "' has mixture components of another number of topics");
    }
  }
}

Eigen::MatrixXd check_theta(const Eigen::Ref<const Eigen::MatrixXd>& theta,
                            const ProportionOptions& options, int expected_topics) {
  options.validate();
  if (expected_topics > 0 && theta.cols() != expected_topics) {
    throw Error("theta has " + std::to_string(theta.cols()) + " topics, the model " +
                std::to_string(expected_topics));
  }
  if (theta.cols() < 2) throw Error("theta needs at least 2 topics (columns)");
  Eigen::MatrixXd out(theta.rows(), theta.cols());
  for (Eigen::Index d = 0; d < theta.rows(); ++d) {
    double sum = 0;
    for (Eigen::Index k = 0; k < theta.cols(); ++k) {
      const double v = theta(d, k);
      if (!(v >= 0.0 && v <= 1.0)) {
        throw Error("theta row " + std::to_string(d) + ", topic " + std::to_string(k) + ": " +
                    number(v) + " is not a proportion in [0, 1]");
      }
      sum += v;
      out(d, k) = std::log(std::max(v, options.floor));
    }
    if (!(std::abs(sum - 1.0) <= options.sum_tolerance)) {
      throw Error("theta row " + std::to_string(d) + " sums to " + number(sum) + ", not 1 within " +
                  number(options.sum_tolerance));
    }
  }
  return out;
}

Eigen::MatrixXd smoothed_log_theta(const Eigen::Ref<const Eigen::MatrixXd>& theta,
                                   const ProportionOptions& options, double smoothing,
                                   int expected_topics) {
  Eigen::MatrixXd out = check_theta(theta, options, expected_topics);
  require(smoothing >= 0.0 && smoothing <= 0.5, "Mixture of Topics: smoothing outside [0, 0.5]");
  if (smoothing == 0.0) return out;
  const double u = smoothing / static_cast<double>(theta.cols());
  out = ((1.0 - smoothing) * theta.array() + u).log().matrix();
  return out;
}

std::string MotFitSummary::brief() const {
  std::ostringstream s;
  s << classes << " objects over " << topics << " topics from " << views << " views";
  int converged = 0;
  for (const auto& f : fits) converged += f.converged ? 1 : 0;
  s << "; " << converged << " of " << fits.size() << " Dirichlet fits converged";
  if (!mixtures.empty()) {
    s << "; Dirichlet components per object:";
    for (const auto& m : mixtures) s << " " << m.components;
  }
  if (shared) s << "; " << shared->brief();
  if (refine_rounds > 0) s << "; " << refine_rounds << " hard-EM rounds";
  if (!bic.empty()) s << "; C chosen by BIC among 1.." << bic.size();
  s.precision(8);
  s << "; log-likelihood " << log_likelihood;
  return s.str();
}

MotFit fit_mot(const Eigen::Ref<const Eigen::MatrixXd>& theta, std::span<const int> labels,
               const std::vector<std::string>& classes, const MotOptions& options) {
  options.validate();
  require(!classes.empty(), "Mixture of Topics: no objects (classes)");
  if (labels.size() != static_cast<std::size_t>(theta.rows())) {
    throw Error("Mixture of Topics: " + std::to_string(labels.size()) + " labels for " +
                std::to_string(theta.rows()) + " theta rows");
  }
  const Eigen::MatrixXd log_theta =
      smoothed_log_theta(theta, options.fit.proportions, options.smoothing);
  const int c = static_cast<int>(classes.size());
  std::vector<int> count(classes.size(), 0);
  for (std::size_t d = 0; d < labels.size(); ++d) {
    if (labels[d] < -1 || labels[d] >= c) {
      throw Error("Mixture of Topics: label " + std::to_string(labels[d]) + " of row " +
                  std::to_string(d) + " is not an object in [0, " + std::to_string(c) + ")");
    }
    if (labels[d] >= 0) ++count[static_cast<std::size_t>(labels[d])];
  }
  for (std::size_t i = 0; i < classes.size(); ++i) {
    if (count[i] < kMinViews) {
      throw Error("Mixture of Topics: object '" + classes[i] + "' has " + std::to_string(count[i]) +
                  " view(s); its Dirichlet needs at least 2 (one view does not fix its precision)");
    }
  }
  MotFit fit = fit_labelled(log_theta, labels, classes, options, true);
  Eigen::MatrixXd labelled(fit.summary.views, log_theta.cols());
  Eigen::Index r = 0;
  for (std::size_t d = 0; d < labels.size(); ++d) {
    if (labels[d] >= 0) labelled.row(r++) = log_theta.row(static_cast<Eigen::Index>(d));
  }
  fit.summary.log_likelihood = mixture_log_likelihood(log_scores(fit.model, labelled));
  fit.summary.message = core::first_line(fit.summary.brief());
  return fit;
}

double mot_bic(const MotFitSummary& summary, int views) {
  const double p = summary.classes * summary.topics + summary.classes - 1.0;
  return -2.0 * summary.log_likelihood + p * std::log(static_cast<double>(views));
}

MotFit fit_mot_unsupervised(const Eigen::Ref<const Eigen::MatrixXd>& theta,
                            const MotOptions& options) {
  options.validate();
  const Eigen::MatrixXd log_theta =
      smoothed_log_theta(theta, options.fit.proportions, options.smoothing);
  const int views = static_cast<int>(theta.rows());
  if (views < kMinViews) {
    throw Error("Mixture of Topics: " + std::to_string(views) +
                " view(s); at least 2 are needed to learn an object");
  }
  const Eigen::MatrixXd x = theta;
  if (options.classes > 0) {
    if (options.classes > views / kMinViews) {
      throw Error("Mixture of Topics: " + std::to_string(options.classes) + " objects from " +
                  std::to_string(views) + " views; each object needs at least 2 views");
    }
    return fit_clusters(x, log_theta, options.classes, options);
  }
  const int largest = std::min(options.max_classes, views / kMinViews);
  std::vector<double> bic;
  MotFit best;
  double best_bic = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= largest; ++k) {
    MotFit f;
    try {
      f = fit_clusters(x, log_theta, k, options);
    } catch (const Error&) {
      bic.push_back(std::numeric_limits<double>::infinity());
      continue;  // no clustering into k objects of 2 views: k is not a candidate
    }
    const double b = mot_bic(f.summary, views);
    bic.push_back(b);
    if (b < best_bic) {
      best_bic = b;
      best = std::move(f);
    }
  }
  ensure(!best.model.objects.empty(), "Mixture of Topics: one object always fits");
  best.summary.bic = std::move(bic);
  best.summary.message = core::first_line(best.summary.brief());
  return best;
}

MotClassification classify_mot(const MotModel& model,
                               const Eigen::Ref<const Eigen::MatrixXd>& theta,
                               const ProportionOptions& options) {
  model.validate();
  const Eigen::MatrixXd log_theta =
      smoothed_log_theta(theta, options, model.smoothing, model.num_topics());
  MotClassification out;
  out.log_score = log_scores(model, log_theta);
  out.posterior.resize(out.log_score.rows(), out.log_score.cols());
  for (Eigen::Index d = 0; d < out.log_score.rows(); ++d) {
    const double z = log_sum_exp(out.log_score.row(d).transpose());
    out.posterior.row(d) = (out.log_score.row(d).array() - z).exp();
  }
  out.predicted = argmax_rows(out.log_score);
  return out;
}

namespace {

// The E-step's bound on log p(words | alpha) for one document (unique words `words`, counts
// `counts`) under topics with log word probabilities log_beta (K x W), the prior alpha.
// At the optimal phi, sum_k phi_wk (E log theta_k + log beta_kw - log phi_wk) is
// log sum_k exp(E log theta_k + log beta_kw), which the bound uses.
double words_bound(const Eigen::VectorXd& alpha, const Eigen::MatrixXd& log_beta,
                   std::span<const std::int32_t> words, std::span<const std::int32_t> counts,
                   const EStepOptions& estep) {
  const Eigen::Index k = alpha.size();
  double n = 0;
  for (const auto c : counts) n += c;
  Eigen::VectorXd gamma = alpha.array() + n / static_cast<double>(k);
  Eigen::VectorXd e_log_theta(k);
  Eigen::VectorXd next(k);
  Eigen::VectorXd phi(k);
  auto expectations = [&] {
    const double dsum = detail::digamma(gamma.sum());
    for (Eigen::Index j = 0; j < k; ++j) e_log_theta(j) = detail::digamma(gamma(j)) - dsum;
  };
  for (int it = 0; it < estep.max_iterations; ++it) {
    expectations();
    next = alpha;
    for (std::size_t i = 0; i < words.size(); ++i) {
      phi = e_log_theta + log_beta.col(words[i]);
      const double m = phi.maxCoeff();
      phi = (phi.array() - m).exp();
      next += (static_cast<double>(counts[i]) / phi.sum()) * phi;
    }
    const double change = (next - gamma).cwiseAbs().mean();
    gamma = next;
    if (change < estep.tolerance) break;
  }
  expectations();
  double bound = std::lgamma(alpha.sum()) - std::lgamma(gamma.sum());
  for (Eigen::Index j = 0; j < k; ++j) {
    bound += std::lgamma(gamma(j)) - std::lgamma(alpha(j)) + (alpha(j) - gamma(j)) * e_log_theta(j);
  }
  for (std::size_t i = 0; i < words.size(); ++i) {
    phi = e_log_theta + log_beta.col(words[i]);
    const double m = phi.maxCoeff();
    bound += static_cast<double>(counts[i]) * (m + std::log((phi.array() - m).exp().sum()));
  }
  return bound;
}

}  // namespace

MotClassification classify_mot_words(const MotModel& model, const LdaModel& lda,
                                     const Corpus& corpus, const EStepOptions& estep) {
  model.validate();
  estep.validate();
  if (lda.num_topics() != model.num_topics()) {
    throw Error("Mixture of Topics: the model has " + std::to_string(model.num_topics()) +
                " topics, the LDA model " + std::to_string(lda.num_topics()));
  }
  if (corpus.num_words() != lda.num_words()) {
    throw Error("Mixture of Topics: the corpus has " + std::to_string(corpus.num_words()) +
                " words, the LDA model " + std::to_string(lda.num_words()));
  }
  const Eigen::MatrixXd log_beta = lda.topic_word().array().log().matrix();
  const Eigen::VectorXd log_p = model.log_prior();
  const auto docs = static_cast<Eigen::Index>(corpus.num_documents());
  MotClassification out;
  out.log_score.resize(docs, model.num_classes());
  for (Eigen::Index d = 0; d < docs; ++d) {
    const DocumentView doc = corpus.document(static_cast<std::size_t>(d));
    for (int c = 0; c < model.num_classes(); ++c) {
      const MotObject& o = model.objects[static_cast<std::size_t>(c)];
      double score = 0;
      if (doc.size() > 0) {
        if (o.mixture.components.empty()) {
          score = words_bound(o.dirichlet.alpha(), log_beta, doc.words, doc.counts, estep);
        } else {
          Eigen::VectorXd parts(static_cast<Eigen::Index>(o.mixture.components.size()));
          for (std::size_t j = 0; j < o.mixture.components.size(); ++j) {
            const DirichletComponent& comp = o.mixture.components[j];
            parts(static_cast<Eigen::Index>(j)) =
                std::log(comp.weight) +
                words_bound(comp.dirichlet.alpha(), log_beta, doc.words, doc.counts, estep);
          }
          score = log_sum_exp(parts);
        }
      }
      out.log_score(d, c) = score + log_p(c);
    }
  }
  out.posterior.resize(out.log_score.rows(), out.log_score.cols());
  for (Eigen::Index d = 0; d < docs; ++d) {
    const double z = log_sum_exp(out.log_score.row(d).transpose());
    out.posterior.row(d) = (out.log_score.row(d).array() - z).exp();
  }
  out.predicted = argmax_rows(out.log_score);
  return out;
}

Eigen::MatrixXd fit_word_multinomials(const Corpus& corpus, std::span<const int> labels,
                                      int classes, double pseudo_count) {
  if (classes < 1) throw Error("word multinomials: need at least one object");
  if (!(pseudo_count > 0 && pseudo_count <= 1e6)) {
    throw Error("word multinomials: the pseudo-count must be in (0, 1e6], got " +
                number(pseudo_count));
  }
  if (labels.size() != corpus.num_documents()) {
    throw Error("word multinomials: " + std::to_string(labels.size()) + " labels for " +
                std::to_string(corpus.num_documents()) + " documents");
  }
  Eigen::MatrixXd counts = Eigen::MatrixXd::Constant(classes, corpus.num_words(), pseudo_count);
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const int c = labels[d];
    if (c < 0) continue;
    if (c >= classes) {
      throw Error("word multinomials: document " + std::to_string(d) + " has label " +
                  std::to_string(c) + " of " + std::to_string(classes) + " objects");
    }
    const DocumentView doc = corpus.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i) counts(c, doc.words[i]) += doc.counts[i];
  }
  for (Eigen::Index c = 0; c < counts.rows(); ++c) {
    const double total = counts.row(c).sum();
    counts.row(c) = (counts.row(c).array() / total).log().matrix();
  }
  return counts;
}

MotClassification pool_word_multinomials(const MotModel& model, const MotClassification& by_words,
                                         const Eigen::MatrixXd& log_phi, const Corpus& corpus,
                                         double weight) {
  model.validate();
  const Eigen::Index classes = model.num_classes();
  const auto docs = static_cast<Eigen::Index>(corpus.num_documents());
  if (log_phi.rows() != classes ||
      log_phi.cols() != static_cast<Eigen::Index>(corpus.num_words())) {
    throw Error("pooled word multinomials: the multinomials are " + std::to_string(log_phi.rows()) +
                " x " + std::to_string(log_phi.cols()) + ", expected " + std::to_string(classes) +
                " objects x " + std::to_string(corpus.num_words()) + " words");
  }
  Eigen::MatrixXd multinomial = Eigen::MatrixXd::Zero(docs, classes);
  for (Eigen::Index d = 0; d < docs; ++d) {
    const DocumentView doc = corpus.document(static_cast<std::size_t>(d));
    for (std::size_t i = 0; i < doc.size(); ++i) {
      multinomial.row(d) +=
          static_cast<double>(doc.counts[i]) * log_phi.col(doc.words[i]).transpose();
    }
  }
  return pool_word_scores(model, by_words, multinomial, weight);
}

MotClassification pool_word_scores(const MotModel& model, const MotClassification& by_words,
                                   const Eigen::MatrixXd& word_scores, double weight) {
  model.validate();
  if (!(weight >= 0 && weight <= 1)) {
    throw Error("pooled word multinomials: the weight must be in [0, 1], got " + number(weight));
  }
  const Eigen::Index classes = model.num_classes();
  const Eigen::Index docs = word_scores.rows();
  if (word_scores.cols() != classes) {
    throw Error("pooled word multinomials: the word scores have " +
                std::to_string(word_scores.cols()) + " objects, expected " +
                std::to_string(classes));
  }
  if (by_words.log_score.rows() != docs || by_words.log_score.cols() != classes) {
    throw Error("pooled word multinomials: the scores by words are not " + std::to_string(docs) +
                " documents x " + std::to_string(classes) + " objects");
  }
  const Eigen::VectorXd log_p = model.log_prior();
  MotClassification out;
  out.log_score.resize(docs, classes);
  for (Eigen::Index d = 0; d < docs; ++d) {
    const Eigen::VectorXd mot = by_words.log_score.row(d).transpose() - log_p;
    out.log_score.row(d) =
        ((1 - weight) * mot + weight * word_scores.row(d).transpose() + log_p).transpose();
  }
  out.posterior.resize(docs, classes);
  for (Eigen::Index d = 0; d < docs; ++d) {
    const double z = log_sum_exp(out.log_score.row(d).transpose());
    out.posterior.row(d) = (out.log_score.row(d).array() - z).exp();
  }
  out.predicted = argmax_rows(out.log_score);
  return out;
}

BackgroundWordModel fit_background_word_model(const Corpus& corpus, std::span<const int> labels,
                                              int classes, double pseudo_count, int iterations) {
  if (iterations < 1) {
    throw Error("background word model: need at least one EM iteration, got " +
                std::to_string(iterations));
  }
  // Checks the labels, classes and pseudo-count; the add-one multinomials p_c.
  const Eigen::MatrixXd log_p = fit_word_multinomials(corpus, labels, classes, pseudo_count);
  const auto words = static_cast<Eigen::Index>(corpus.num_words());
  Eigen::MatrixXd counts = Eigen::MatrixXd::Zero(classes, words);
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const int c = labels[d];
    if (c < 0) continue;
    const DocumentView doc = corpus.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i) counts(c, doc.words[i]) += doc.counts[i];
  }
  // b(w) proportional to min_c p_c(w).
  Eigen::VectorXd background = log_p.colwise().minCoeff().transpose().array().exp().matrix();
  background /= background.sum();
  BackgroundWordModel m;
  m.log_background = background.array().log().matrix();
  m.log_object.resize(classes, words);
  m.background_share = Eigen::VectorXd::Zero(classes);
  for (Eigen::Index c = 0; c < classes; ++c) {
    const double total = counts.row(c).sum();
    Eigen::VectorXd q = log_p.row(c).transpose().array().exp().matrix();
    double s = 0.5;
    if (total > 0) {
      for (int it = 0; it < iterations; ++it) {
        Eigen::VectorXd own = Eigen::VectorXd::Constant(words, pseudo_count);
        double bg = 0;
        for (Eigen::Index w = 0; w < words; ++w) {
          const double a = s * background(w);
          const double b = (1 - s) * q(w);
          const double r = a + b > 0 ? a / (a + b) : 0.0;  // the background's responsibility
          bg += counts(c, w) * r;
          own(w) += counts(c, w) * (1 - r);
        }
        s = bg / total;
        q = own / own.sum();
      }
    }
    m.log_object.row(c) = q.array().log().matrix().transpose();
    m.background_share(c) = s;
  }
  return m;
}

Eigen::MatrixXd background_word_scores(const BackgroundWordModel& model, const Corpus& corpus,
                                       int iterations) {
  const Eigen::Index classes = model.log_object.rows();
  const auto words = static_cast<Eigen::Index>(corpus.num_words());
  if (model.log_object.cols() != words || model.log_background.size() != words) {
    throw Error("background word scores: the model has " + std::to_string(model.log_object.cols()) +
                " words (background " + std::to_string(model.log_background.size()) +
                "), the corpus " + std::to_string(words));
  }
  if (iterations < 1) {
    throw Error("background word scores: need at least one EM iteration, got " +
                std::to_string(iterations));
  }
  const Eigen::VectorXd background = model.log_background.array().exp().matrix();
  const auto docs = static_cast<Eigen::Index>(corpus.num_documents());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(docs, classes);
  for (Eigen::Index d = 0; d < docs; ++d) {
    const DocumentView doc = corpus.document(static_cast<std::size_t>(d));
    double total = 0;
    for (std::size_t i = 0; i < doc.size(); ++i) total += doc.counts[i];
    if (total <= 0) continue;
    for (Eigen::Index c = 0; c < classes; ++c) {
      const auto likelihood = [&](double s) {
        double l = 0;
        for (std::size_t i = 0; i < doc.size(); ++i) {
          const auto w = static_cast<Eigen::Index>(doc.words[i]);
          l += doc.counts[i] *
               std::log(s * background(w) + (1 - s) * std::exp(model.log_object(c, w)));
        }
        return l;
      };
      double s = 0.5;
      for (int it = 0; it < iterations; ++it) {
        double bg = 0;
        for (std::size_t i = 0; i < doc.size(); ++i) {
          const auto w = static_cast<Eigen::Index>(doc.words[i]);
          const double a = s * background(w);
          const double b = (1 - s) * std::exp(model.log_object(c, w));
          bg += doc.counts[i] * (a + b > 0 ? a / (a + b) : 0.0);
        }
        s = bg / total;
      }
      out(d, c) = likelihood(s);
    }
  }
  return out;
}

MotUpdateSummary update_mot(MotModel& model, const Eigen::Ref<const Eigen::MatrixXd>& theta,
                            const std::vector<std::string>& labels, const MotOptions& options) {
  options.validate();
  model.validate();
  if (labels.size() != static_cast<std::size_t>(theta.rows())) {
    throw Error("Mixture of Topics update: " + std::to_string(labels.size()) + " labels for " +
                std::to_string(theta.rows()) + " theta rows");
  }
  const Eigen::MatrixXd log_theta =
      smoothed_log_theta(theta, options.fit.proportions, model.smoothing, model.num_topics());
  // Group the new views by object, in order of first appearance.
  std::vector<std::string> order;
  std::map<std::string, std::vector<Eigen::Index>> rows;
  for (std::size_t d = 0; d < labels.size(); ++d) {
    if (labels[d].empty()) continue;
    auto [it, fresh] = rows.try_emplace(labels[d]);
    if (fresh) order.push_back(labels[d]);
    it->second.push_back(static_cast<Eigen::Index>(d));
  }
  MotModel next = model;
  MotUpdateSummary summary;
  core::Rng rng(options.seed);
  for (const auto& name : order) {
    const auto& idx = rows[name];
    DirichletStats fresh(model.num_topics());
    for (const Eigen::Index d : idx) fresh.add_log(log_theta.row(d).transpose());
    const auto n = static_cast<int>(idx.size());
    summary.views += n;
    auto it = std::find_if(next.objects.begin(), next.objects.end(),
                           [&](const MotObject& o) { return o.name == name; });
    if (it == next.objects.end()) {
      if (n < kMinViews) {
        throw Error("Mixture of Topics update: new object '" + name + "' has " + std::to_string(n) +
                    " view(s); its Dirichlet needs at least 2");
      }
      DirichletFit f = fit_dirichlet(fresh, options.fit);
      summary.fits.push_back(f.summary);
      next.objects.push_back(
          MotObject{name, fresh, std::move(f.dirichlet), static_cast<double>(n)});
      if (options.components > 1) {
        Eigen::MatrixXd rows_new(n, log_theta.cols());
        for (int i = 0; i < n; ++i)
          rows_new.row(i) = log_theta.row(idx[static_cast<std::size_t>(i)]);
        DirichletMixtureSummary m;
        next.objects.back().mixture = object_mixture(rows_new, options, next.objects.size() - 1, m);
        summary.mixtures.push_back(std::move(m));
      }
      ++summary.new_objects;
      continue;
    }
    const auto object = static_cast<std::uint64_t>(it - next.objects.begin());
    DirichletStats stats = it->stats;
    if (options.update == MotUpdateRule::kExact) {
      if (options.forgetting < 1.0) stats.scale(options.forgetting);
      stats.merge(fresh);
      it->views = it->views * options.forgetting + n;
      if (!it->mixture.components.empty()) {
        summary.mixtures.push_back(update_mixture_exact(it->mixture, log_theta, idx, options));
      }
    } else {
      // Thesis 8.1.2: as many samples of the old Dirichlet (or mixture) as new views, appended,
      // refitted.
      stats = DirichletStats(model.num_topics());
      const bool mixed = !it->mixture.components.empty();
      Eigen::MatrixXd rows_all(2 * n, log_theta.cols());
      for (int i = 0; i < n; ++i) {
        const Dirichlet* from = &it->dirichlet;
        if (mixed) {
          double u = rng.uniform();
          for (const auto& c : it->mixture.components) {
            from = &c.dirichlet;
            u -= c.weight;
            if (u < 0) break;
          }
        }
        rows_all.row(i) = from->sample_log(rng).transpose();
        stats.add_log(rows_all.row(i).transpose());
      }
      for (int i = 0; i < n; ++i)
        rows_all.row(n + i) = log_theta.row(idx[static_cast<std::size_t>(i)]);
      stats.merge(fresh);
      summary.resampled += n;
      it->views += n;
      if (mixed) {
        MotOptions o = options;
        o.components = std::max(options.components, it->mixture.num_components());
        DirichletMixtureSummary m;
        it->mixture = object_mixture(rows_all, o, object, m);
        summary.mixtures.push_back(std::move(m));
      }
    }
    DirichletFit f = fit_dirichlet(stats, options.fit);
    summary.fits.push_back(f.summary);
    it->stats = std::move(stats);
    it->dirichlet = std::move(f.dirichlet);
  }
  if (options.shared_precision) (void)share_precision(next, options);
  model = std::move(next);
  return summary;
}

}  // namespace proprio::topics
