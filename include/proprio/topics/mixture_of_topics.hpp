#pragma once
// The Mixture of Topics object model (thesis 7.1): LDA gives each view (document) of an object its
// topic proportions theta; the thetas of one object c are modelled as Dir(theta | omega_c) (eq
// 7.2), omega_c by maximum likelihood (Minka 2003, proprio/topics/dirichlet_fit.hpp), and a new
// view is classified by Bayes over the objects (eq 7.3):
//   p(c | theta) = Dir(theta | omega_c) p(c) / sum_c' Dir(theta | omega_c') p(c').
// Learning is supervised (labelled views), unsupervised (k-means over theta, thesis 7.3.3; the
// number of objects given or chosen by BIC) or online (thesis 8.1.2: new views update a model).
//
// Theta rows are checked where they enter (check_theta): every entry in [0, 1] and not NaN, each
// row summing to 1 within ProportionOptions::sum_tolerance (1e-5), or Error naming the row (from
// 0). Entries below the floor (1e-300 by default) are raised to it before their log is taken.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_fit.hpp"
#include "proprio/topics/dirichlet_mixture.hpp"
#include "proprio/topics/dirichlet_stats.hpp"
#include "proprio/topics/estep_options.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::topics {

/// How the prior p(c) of eq 7.3 is set.
enum class MotPrior {
  kViews,    ///< p(c) proportional to the views c was learned from
  kUniform,  ///< p(c) = 1 / C
};
inline constexpr core::ChoiceNames<MotPrior, 2> kMotPriorNames{
    {{"views", MotPrior::kViews}, {"uniform", MotPrior::kUniform}}};

/// How new views update an object's Dirichlet (update_mot).
enum class MotUpdateRule {
  /// Merge the new views' sufficient statistics into the object's (after multiplying the old
  /// count by `forgetting`) and refit: with forgetting 1 the same model as fitting all views at
  /// once. The default: see docs/results/mot.md for the measurements.
  kExact,
  /// Thesis 8.1.2's 50:50 rule: draw as many samples of the old Dirichlet as there are new views,
  /// append the new views, refit on those alone (the old views are forgotten, their Dirichlet
  /// weighs as much as the new batch).
  kResample,
};
inline constexpr core::ChoiceNames<MotUpdateRule, 2> kMotUpdateRuleNames{
    {{"exact", MotUpdateRule::kExact}, {"resample", MotUpdateRule::kResample}}};

struct MotOptions {
  MotPrior prior = MotPrior::kViews;
  /// Unsupervised: the number of objects C; 0 chooses it in [1, max_classes] by the smallest BIC
  /// of the Dirichlet mixture (choose_num_classes).
  int classes = 0;
  int max_classes = 10;     ///< the largest C tried when choosing (further bounded by views / 2)
  int kmeans_restarts = 8;  ///< k-means++ starts; the lowest within-cluster sum of squares wins
  int kmeans_iterations = 100;  ///< Lloyd iterations per start at most
  /// Unsupervised: hard-EM rounds after k-means (reassign each view to its most probable object
  /// under the fitted Dirichlets, refit), stopping early when no view moves; 0 keeps k-means'.
  int refine_iterations = 10;
  MotUpdateRule update = MotUpdateRule::kExact;
  /// kExact: the old statistics' count is multiplied by this before new views merge in (1: no
  /// forgetting).
  double forgetting = 1.0;
  std::uint64_t seed = 1;  ///< k-means starts and the resample rule's draws
  /// Theta smoothing s in [0, 0.5]: every theta (training, update and classified) is replaced by
  /// (1 - s) theta + s / T before its log is taken (MotModel::smoothing keeps it, so classifying
  /// uses the training's). A view's theta from N words puts about alpha / N on the topics it does
  /// not use, so without smoothing log theta of those topics, which dominate the Dirichlet's
  /// density when omega_ck < 1, varies with the number of words of the view rather than with the
  /// object; s bounds that tail at s / T. 0 keeps theta as it is. docs/results/mot.md measures it.
  double smoothing = 0.0;
  /// Supervised fits and updates: each object a mixture of Dirichlets (proprio/topics/
  /// dirichlet_mixture.hpp) with at most this many components, their number chosen per object
  /// by BIC over its views (EM, the Minka fit as M-step). 1 (the default, the thesis's): one
  /// Dirichlet per object; kept as the default because on the scatter report (docs/results/
  /// mot.md, fourth round) the mixture, though best on 4 objects (88.2% against 81.8%), fell
  /// below one Dirichlet on two of five 3-object seeds. The unsupervised fit keeps one Dirichlet
  /// per object.
  int components = 1;
  /// With components > 1: EM starts per number of components, EM iterations per start at most,
  /// the smallest effective number of views a component may have (see DirichletMixtureOptions).
  int component_restarts = 3;
  int component_iterations = 100;
  double component_min_views = 5;
  /// Supervised fits and updates: one precision s shared by every object's Dirichlet, a mean per
  /// object (fit_dirichlets_shared_precision): a cheaper regulariser than the mixture. Not with
  /// components > 1.
  bool shared_precision = false;
  /// The Dirichlet fits (tolerance, iterations, precision bound) and the theta checks (floor,
  /// row-sum tolerance).
  DirichletFitOptions fit;

  /// Throws Error naming the first bad option (bounds from describe, then fit.validate()).
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.prior, {"prior", "p(c): views (proportional to training views) or uniform"},
             kMotPriorNames);
    v(self.classes,
      {"classes", "Unsupervised: number of objects (0: chosen by BIC)", core::between(0, 100000)});
    v(self.max_classes, {"max_classes", "Unsupervised: largest number of objects tried by BIC",
                         core::between(1, 100000)});
    v(self.kmeans_restarts, {"kmeans_restarts", "k-means++ starts", core::between(1, 1000)});
    v(self.kmeans_iterations,
      {"kmeans_iterations", "Lloyd iterations per start", core::between(1, 100000)});
    v(self.refine_iterations,
      {"refine_iterations", "Hard-EM rounds after k-means", core::between(0, 1000)});
    v.choice(self.update, {"update", "Online rule: exact (merge statistics) or resample (50:50)"},
             kMotUpdateRuleNames);
    v(self.forgetting,
      {"forgetting", "Exact rule: factor on the old views' weight", core::Bounds{0, 1, true}});
    v(self.seed, {"seed", "Seed of k-means and of the resample rule"});
    v(self.smoothing, {"smoothing", "Theta smoothing s: (1 - s) theta + s / T before the log",
                       core::Bounds{0, 0.5, false}});
    v(self.components,
      {"components", "Supervised: most Dirichlet components per object (chosen by BIC; 1: one)",
       core::between(1, 1000)});
    v(self.component_restarts,
      {"component_restarts", "EM starts per number of components", core::between(1, 1000)});
    v(self.component_iterations,
      {"component_iterations", "EM iterations per start", core::between(1, 100000)});
    v(self.component_min_views,
      {"component_min_views", "Fewest effective views of a component", core::Bounds{2, 1e9}});
    v(self.shared_precision,
      {"shared_precision", "Supervised: one precision shared by every object's Dirichlet"});
  }
};

/// One object's model.
struct MotObject {
  std::string name;
  DirichletStats stats;  ///< the views it was fitted on (count, mean log theta)
  Dirichlet dirichlet;   ///< omega_c (the object's density unless `mixture` has components)
  double views = 0;      ///< views learned from (the weight behind p(c) for MotPrior::kViews)
  /// MotOptions::components > 1 and BIC chose more than one: the object's density is this
  /// mixture of Dirichlets (`dirichlet` stays the one-Dirichlet fit of the same views). Empty:
  /// `dirichlet` alone.
  DirichletMixture mixture{};

  /// log p(theta | c) from log theta: the mixture's when it has components, else `dirichlet`'s.
  [[nodiscard]] double log_density_of_log(const Eigen::Ref<const Eigen::VectorXd>& log_theta) const;
};

/// A Mixture of Topics over T topics.
struct MotModel {
  std::vector<MotObject> objects;
  MotPrior prior = MotPrior::kViews;
  /// The theta smoothing the model was fitted with (MotOptions::smoothing); classify_mot and
  /// update_mot apply it to their theta.
  double smoothing = 0.0;

  [[nodiscard]] int num_classes() const { return static_cast<int>(objects.size()); }
  /// T; 0 for an empty model.
  [[nodiscard]] int num_topics() const { return objects.empty() ? 0 : objects[0].dirichlet.dim(); }
  /// log p(c) for each object (natural log).
  [[nodiscard]] Eigen::VectorXd log_prior() const;
  [[nodiscard]] std::vector<std::string> names() const;
  /// Throws Error unless there is at least one object, all of one dimension T >= 2, with views > 0.
  void validate() const;
};

/// Checks n x T theta (see the file comment) and returns log(max(theta, floor)). Error names the
/// row and the problem; `expected_topics` > 0 also checks the number of columns.
Eigen::MatrixXd check_theta(const Eigen::Ref<const Eigen::MatrixXd>& theta,
                            const ProportionOptions& options, int expected_topics = 0);
/// check_theta, then log((1 - smoothing) theta + smoothing / T) (MotOptions::smoothing; 0: the
/// same as check_theta).
Eigen::MatrixXd smoothed_log_theta(const Eigen::Ref<const Eigen::MatrixXd>& theta,
                                   const ProportionOptions& options, double smoothing,
                                   int expected_topics = 0);

struct MotFitSummary {
  int views = 0;
  int classes = 0;
  int topics = 0;
  std::vector<DirichletFitSummary> fits;  ///< one per object
  /// MotOptions::components > 1: one per object (components, EM iterations, why it stopped).
  std::vector<DirichletMixtureSummary> mixtures;
  /// MotOptions::shared_precision: the joint fit.
  std::optional<SharedPrecisionSummary> shared;
  /// Unsupervised: the k-means within-cluster sum of squares of the chosen start, the hard-EM
  /// rounds run, the BIC of each C tried (index C - 1; empty when C was given).
  double kmeans_sse = 0;
  int refine_rounds = 0;
  std::vector<double> bic;
  /// The mixture's log-likelihood of the training views, sum_d log sum_c p(c) Dir(theta_d |
  /// omega_c), nats.
  double log_likelihood = 0;
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;
};

struct MotFit {
  MotModel model;
  MotFitSummary summary;
  /// The object of each training view (the labels given, or the clusters found).
  std::vector<int> assignment;
};

/// Supervised fit (thesis 7.1): omega_c by maximum likelihood over the views labelled c. theta is
/// D x T, labels[d] in [0, C) or -1 (ignored), classes the C names. Throws Error on bad theta
/// (naming the row), a label out of range, or an object with fewer than 2 views (naming it: one
/// view does not determine a Dirichlet's precision).
MotFit fit_mot(const Eigen::Ref<const Eigen::MatrixXd>& theta, std::span<const int> labels,
               const std::vector<std::string>& classes, const MotOptions& options = {});

/// Unsupervised fit (thesis 7.3.3): k-means++ over theta (options.kmeans_restarts starts,
/// seeded), a Dirichlet per cluster, then hard-EM refinement; C = options.classes, or chosen by
/// BIC when 0. Objects are named object_1 .. object_C. Throws Error on bad theta, fewer than 2
/// views, C > views / 2 (every object needs 2 views), or when no start gives every cluster 2
/// views.
MotFit fit_mot_unsupervised(const Eigen::Ref<const Eigen::MatrixXd>& theta,
                            const MotOptions& options = {});

/// BIC = -2 L + p ln D of the unsupervised fit with C objects, p = C T + C - 1 free parameters
/// (alpha per object and the prior weights), L the mixture log-likelihood: the smaller the
/// better. choose C = argmin over [1, min(max_classes, D / 2)].
double mot_bic(const MotFitSummary& summary, int views);

// NOLINTNEXTLINE(bugprone-exception-escape)
struct MotClassification {
  /// D x C posterior p(c | theta_d) (eq 7.3), rows sum to 1.
  Eigen::MatrixXd posterior;
  /// D x C log Dir(theta_d | omega_c) + log p(c), nats (unnormalised log posterior).
  Eigen::MatrixXd log_score;
  std::vector<int> predicted;  ///< argmax_c per row (ties: lowest c)
};

/// Classifies each row of theta (D x T, T the model's) by eq 7.3. Throws Error on bad theta
/// (naming the row) or another T.
MotClassification classify_mot(const MotModel& model,
                               const Eigen::Ref<const Eigen::MatrixXd>& theta,
                               const ProportionOptions& options = {});

/// Classifies documents by their words instead of a point theta: each object's marginal
/// likelihood of the document under LDA with the object's Dirichlet as the prior of theta,
///   log p(w_d | c) = log int prod_n sum_k theta_k beta_k,w_dn Dir(theta | omega_c) dtheta,
/// bounded below by the variational E-step run with alpha = omega_c (eq B.16-B.18 with an
/// asymmetric prior; beta the topics' posterior mean LdaModel::topic_word()), whose bound (the
/// ELBO) stands for it; an object with a mixture sums its components, log sum_j w_j exp(ELBO_j).
/// log_score = that + log p(c). The object's Dirichlet models the whole view rather than one
/// theta, so a view whose words spread over several topics is not forced into one corner. The
/// model's smoothing is not used. An empty document scores log p(c). Throws Error when the
/// corpus, LDA model and Mixture of Topics disagree on W or T.
MotClassification classify_mot_words(const MotModel& model, const LdaModel& lda,
                                     const Corpus& corpus, const EStepOptions& estep = {});

/// Each object's multinomial over the words, an addition to the thesis's model (session 22 of
/// docs/results/mot.md): row c is log p(w | c) from the pooled word counts of the documents
/// labelled c plus `pseudo_count` for every word (add-one smoothing by default). A label < 0
/// leaves its document out. Throws Error when labels and documents differ in number, a label is
/// >= classes, classes < 1 or pseudo_count is not in (0, 1e6].
Eigen::MatrixXd fit_word_multinomials(const Corpus& corpus, std::span<const int> labels,
                                      int classes, double pseudo_count = 1.0);

/// The Mixture of Topics by words pooled with the objects' word multinomials (log-linear, a
/// product of the two experts): with L_c(w_d) = by_words.log_score(d, c) - log p(c) (the MoT's
/// bound on log p(w_d | c), classify_mot_words),
///   log_score(d, c) = (1 - weight) L_c(w_d) + weight sum_n log p(w_dn | c) + log p(c),
/// p(c) the model's prior and p(w | c) = exp(log_phi(c, w)) (fit_word_multinomials). weight 0
/// gives classify_mot_words' scores, weight 1 multinomial naive Bayes with the MoT's prior. An
/// empty document scores (1 - weight) L_c + log p(c) as before. Throws Error on weight outside
/// [0, 1], a log_phi with other than C rows or other than the corpus's W columns, or a by_words
/// with other than D x C scores.
MotClassification pool_word_multinomials(const MotModel& model, const MotClassification& by_words,
                                         const Eigen::MatrixXd& log_phi, const Corpus& corpus,
                                         double weight);

/// The objects' word multinomials with a background shared by all objects (session 30 of
/// docs/results/learn-history.md, an addition to the thesis's model): a view's words are a mixture
///   p(w | c, s) = s b(w) + (1 - s) q_c(w),
/// b the background, q_c the object's own words and s in [0, 1] the view's share of background.
/// b(w) is proportional to min_c p_c(w), p_c the add-one multinomials of fit_word_multinomials
/// (what every object's views hold: the table, the backdrop, shared neighbours); q_c and each
/// object's training share of background are fitted by EM on the pooled counts of its views.
/// A view is then scored with its own share s (background_word_scores), so that how much table
/// a view shows no longer votes for the object whose training views showed most table.
struct BackgroundWordModel {
  Eigen::MatrixXd log_object;        ///< C x W: log q_c(w)
  Eigen::VectorXd log_background;    ///< W: log b(w)
  Eigen::VectorXd background_share;  ///< C: each object's fitted training share of background
};

/// Fits BackgroundWordModel to the documents labelled 0..classes-1 (a label < 0 leaves its
/// document out; pseudo_count added to every word of q_c in each M-step, as
/// fit_word_multinomials; `iterations` EM steps). Throws Error as fit_word_multinomials, and for
/// iterations < 1.
BackgroundWordModel fit_background_word_model(const Corpus& corpus, std::span<const int> labels,
                                              int classes, double pseudo_count = 1.0,
                                              int iterations = 100);

/// D x C: each document's log-likelihood under each object with its own background share,
///   max over s in [0, 1] of sum_n log(s b(w_dn) + (1 - s) q_c(w_dn))
/// (the share found by `iterations` EM steps from 0.5; the objective is concave in s). An empty
/// document scores 0. Throws Error when the model's W differs from the corpus's or the model's
/// parts disagree in size.
Eigen::MatrixXd background_word_scores(const BackgroundWordModel& model, const Corpus& corpus,
                                       int iterations = 50);

/// pool_word_multinomials with the multinomial term given as a D x C matrix of log-likelihoods
/// (e.g. background_word_scores): log_score(d, c) = (1 - weight) L_c(w_d) + weight
/// word_scores(d, c) + log p(c). Throws Error on weight outside [0, 1] or sizes that disagree.
MotClassification pool_word_scores(const MotModel& model, const MotClassification& by_words,
                                   const Eigen::MatrixXd& word_scores, double weight);

struct MotUpdateSummary {
  int views = 0;                          ///< new views
  int new_objects = 0;                    ///< labels not in the model before
  int resampled = 0;                      ///< samples drawn from old Dirichlets (kResample)
  std::vector<DirichletFitSummary> fits;  ///< the refits, in order of the objects updated
  /// Objects with a mixture: the refit of each (in the same order as their objects in `fits`).
  std::vector<DirichletMixtureSummary> mixtures;
};

/// Online update (thesis 8.1.2) with new labelled views: theta D x T, labels[d] naming an object
/// (an existing name updates it, a new name adds an object, which needs >= 2 views; an empty
/// name is skipped). options.update picks the rule, options.forgetting and options.seed apply.
/// An object with a mixture: the exact rule merges each new view into every component with its
/// responsibility under the old mixture (weights from the merged counts) and refits each
/// component (one online EM step); the resample rule draws its samples from the mixture and
/// refits the mixture by EM (options.components bounds it). A new object gets a mixture when
/// options.components > 1. options.shared_precision refits every object's Dirichlet jointly.
/// Throws Error on bad theta or a new object with fewer than 2 views; the model is unchanged then.
MotUpdateSummary update_mot(MotModel& model, const Eigen::Ref<const Eigen::MatrixXd>& theta,
                            const std::vector<std::string>& labels, const MotOptions& options = {});

}  // namespace proprio::topics
