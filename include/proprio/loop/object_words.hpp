#pragma once
// Object words (thesis 8.1.2, SPEC §6) and top-down recognition (8.1.3, eqs 8.4-8.7).
//
// An object's words are points in descriptor space (SIFT descriptors scaled to unit length): after
// the first push, the modes of a mean shift over the object's segmented descriptors; after each
// later push every word moves toward its nearest new descriptor by the incremental mean
// w <- (N w + d) / (N + 1) (the thesis prints N/(N+1) (w + d): a typo, SPEC §6). Each segmented
// frame i gives a distribution over the words, p(w | i) = sum_d N(w | d, Sigma) p(d | i) with
// p(d | i) uniform over the frame's descriptors (eq 8.3); these are Dirichlet distributed
// (Minka's fit, topics/dirichlet_fit.hpp), updated after each push either by exact merging of
// the sufficient statistics or by the thesis's 50:50 rule (as many samples of the old Dirichlet
// as the push has frames, appended to the new frames, refitted).
//
// Top-down recognition: p(d) = sum_w N(d | w, Sigma_hat) p(w) for every descriptor d of a look
// (p(w) the Dirichlet's mean), p(x) = sum_d N(x | x_d, Sigma) p(d) in the image, and the region
// p(x) >= kappa max p(x) (its connected part holding the maximum) whose word distribution is the
// most probable under the object's Dirichlet gives kappa.

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/random.hpp"
#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_stats.hpp"

namespace proprio::loop {

/// How an object's Dirichlet over its words is updated after a push.
enum class DirichletUpdate {
  kExact,      ///< merge the new frames' sufficient statistics with the old ones
  kFiftyFifty  ///< the thesis's rule: sample the old Dirichlet once per new frame, refit
};
inline constexpr core::ChoiceNames<DirichletUpdate, 2> kDirichletUpdateNames{
    {{"exact", DirichletUpdate::kExact}, {"fifty-fifty", DirichletUpdate::kFiftyFifty}}};

struct ObjectWordOptions {
  /// Mean-shift bandwidth (Gaussian kernel sigma) over unit descriptors.
  double bandwidth = 0.2;
  int max_words = 60;          ///< at most this many words (the modes with most support)
  int mean_shift_seeds = 200;  ///< descriptors the mean shift starts from (seeded sample)
  /// Sigma = sigma2 I of N(w | d, Sigma) (eq 8.3) and Sigma_hat of p(d) (8.4), unit descriptors
  /// (the thesis's 0.1 I).
  double sigma2 = 0.1;
  /// p(x) (8.5): Gaussian blur of the descriptors' p(d), px.
  double density_sigma = 10.0;
  /// Thresholds kappa tried, fractions of max p(x) (8.7).
  std::vector<double> thresholds{0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
  int min_features = 8;  ///< a recognised region needs this many descriptors
  DirichletUpdate update = DirichletUpdate::kExact;
  void validate() const;
};

/// Descriptors (N x 128 CV_32F) scaled to unit L2 length (zero rows stay zero), as CV_64F.
Eigen::MatrixXd unit_descriptors(const cv::Mat& descriptors);

/// Modes of a Gaussian mean shift over the rows of `x` (unit descriptors), started from at most
/// `seeds` rows drawn by `rng`, merged when closer than bandwidth / 2; at most max_words modes
/// (those that most starts reached), each row of the result a word. Empty x: no words.
Eigen::MatrixXd mean_shift_words(const Eigen::MatrixXd& x, const ObjectWordOptions& options,
                                 core::Rng& rng);

/// p(w | i) of one frame (eq 8.3): rows of `x` are the frame's unit descriptors, rows of `words`
/// the words; the result sums to 1 (a floor of 1e-12 keeps every entry positive).
Eigen::VectorXd frame_word_distribution(const Eigen::MatrixXd& words, const Eigen::MatrixXd& x,
                                        double sigma2);

/// What top-down recognition found in one look.
struct TopDownResult {
  bool found = false;
  cv::Mat1b mask;          ///< the chosen region (255), image size
  cv::Mat1f px;            ///< p(x), scaled to max 1
  double kappa = 0;        ///< the chosen threshold (fraction of max p(x))
  double log_density = 0;  ///< log Dir of the region's p(w | region), nats
  int features = 0;        ///< descriptors in the region
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< their mean position, px
  std::string message;
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

/// One object's words, their counts N, and the Dirichlet of its frames' word distributions.
class ObjectModel {
 public:
  /// Learns the words from the first push's frames (descriptors per frame, unit rows): mean shift
  /// over all of them; then the Dirichlet of the frames' p(w | i). False (nothing learned) when
  /// fewer than 2 words or 2 frames come out.
  bool first_push(const std::vector<Eigen::MatrixXd>& frames, const ObjectWordOptions& options,
                  core::Rng& rng);
  /// A later push: every word moves toward its nearest descriptor by the incremental mean, then
  /// the Dirichlet is updated by options.update (both kept for measurement: see
  /// predictive_log_likelihood). Frames with no descriptors are skipped.
  void later_push(const std::vector<Eigen::MatrixXd>& frames, const ObjectWordOptions& options,
                  core::Rng& rng);
  [[nodiscard]] bool learned() const { return dirichlet_.has_value(); }
  [[nodiscard]] const Eigen::MatrixXd& words() const { return words_; }
  [[nodiscard]] int num_words() const { return static_cast<int>(words_.rows()); }
  [[nodiscard]] const topics::Dirichlet& dirichlet() const { return *dirichlet_; }
  /// Mean log Dir(p(w | i)) of `frames` under the exact and the 50:50 Dirichlet, nats per frame
  /// (before they are added): how well each predicts the next push. nullopt before learned().
  [[nodiscard]] std::optional<std::pair<double, double>> predictive_log_likelihood(
      const std::vector<Eigen::MatrixXd>& frames, const ObjectWordOptions& options) const;
  /// log p(d) (eq 8.4) of each row of `x` (unit descriptors), up to a constant shared by all
  /// objects with the same sigma2.
  [[nodiscard]] Eigen::VectorXd log_p_descriptors(const Eigen::MatrixXd& x,
                                                  const ObjectWordOptions& options) const;

 private:
  topics::DirichletStats frame_stats(const std::vector<Eigen::MatrixXd>& frames,
                                     const ObjectWordOptions& options) const;
  Eigen::MatrixXd words_;
  std::vector<double> counts_;
  topics::DirichletStats stats_;                ///< exact: every frame so far
  std::optional<topics::Dirichlet> dirichlet_;  ///< by options.update
  std::optional<topics::Dirichlet> exact_;
  std::optional<topics::Dirichlet> fifty_;
};

/// Top-down recognition of `model` in a look whose features are at `points` (px) with unit
/// descriptors `x` (eqs 8.4-8.7); `size` the image size. Not found when the model is not learned,
/// there are no features, or no threshold's region holds options.min_features descriptors.
TopDownResult recognise_top_down(const ObjectModel& model, const std::vector<cv::Point2f>& points,
                                 const Eigen::MatrixXd& x, cv::Size size,
                                 const ObjectWordOptions& options);

}  // namespace proprio::loop
