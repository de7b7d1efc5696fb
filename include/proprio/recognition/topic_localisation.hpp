#pragma once
// Topic localisation maps (thesis 7.3.1, eqs 7.6-7.7): where in an image each topic's features
// lie. For a document (an image's features y_k at pixels x_k, each quantised to its nearest word
// w(k)) with topic proportions theta-hat from LDA's E-step, the map of topic z_i is the density
//   p(x | z_i, theta) = sum_k N(x | x_k, Sigma) p(y_k | z_i, theta)          (eq 7.7)
// with p(y | z_i, theta) = sum_j p(y | w_j) p(w_j | z_i) (eq 7.6). Descriptors are quantised to
// one word (p(y | w_j) is 1 for the nearest word, 0 for the others: the hard limit of eq 7.6's
// Gaussian), so p(y_k | z_i) = beta_{i, w(k)}, the topic's probability of that word. Optionally
// (MapWeight::kResponsibility) the feature weighs by the topic's share of it given the image,
// p(z_i | y_k, theta) = theta_i beta_{i,w(k)} / sum_j theta_j beta_{j,w(k)}, which is where theta
// enters and which makes the maps of different topics add up to the feature density.

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::recognition {

/// How a feature weighs in a topic's map.
enum class MapWeight {
  kWordGivenTopic,  ///< p(y_k | z_i) = beta_{i,w(k)} (eqs 7.6-7.7 as printed)
  kResponsibility,  ///< p(z_i | y_k, theta)
};
inline constexpr core::ChoiceNames<MapWeight, 2> kMapWeightNames{
    {{"word", MapWeight::kWordGivenTopic}, {"responsibility", MapWeight::kResponsibility}}};

struct TopicMapOptions {
  double sigma = 8.0;  ///< Sigma = sigma^2 I, px
  MapWeight weight = MapWeight::kWordGivenTopic;
  topics::InferenceOptions inference;  ///< theta-hat of the image's document

  /// Throws Error naming the option out of bounds.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.sigma,
      {"sigma", "Localisation maps: Gaussian standard deviation, px", core::Bounds{0.1, 1000}});
    v.choice(self.weight,
             {"map_weight", "A feature's weight: word (p(y|z), eq 7.6) or responsibility"},
             kMapWeightNames);
  }
};

struct TopicMaps {
  /// One CV_64F map per topic of the image's size: p(x | z_i, theta) over the pixels, summing to
  /// 1 (all zeros for a topic none of whose words is in the image, or an image without features).
  std::vector<cv::Mat> density;
  Eigen::VectorXd theta;        ///< theta-hat of the image's document (E[theta], eq B.17)
  std::vector<cv::Point> peak;  ///< each map's most probable pixel ((-1, -1) for a zero map)
};

/// The localisation map of every topic of `model` for an image of `image_size` whose features
/// are `f` (keypoints in pixels; descriptors quantised by `vocabulary`). The sum of eq 7.7 is
/// evaluated by placing each feature's weight at its nearest pixel and convolving with the
/// Gaussian (cv::GaussianBlur, zero outside the image, then normalised over the image). Throws
/// Error when the model and vocabulary disagree on the number of words, or on bad options.
TopicMaps topic_maps(const features::Features& f, cv::Size image_size,
                     const topics::LdaModel& model, const features::Vocabulary& vocabulary,
                     const TopicMapOptions& options = {});

/// A map as an 8-bit image for a person: the density scaled so that its maximum is 255, through
/// OpenCV's JET colour map; with `over` (an image of the same size), blended half and half.
cv::Mat topic_map_image(const cv::Mat& density, const cv::Mat& over = {});

/// Writes topic_<i>.png (from 1, as the thesis numbers topics) for every map into `dir` (created),
/// each blended over `image` when given. Returns the files written.
std::vector<std::filesystem::path> write_topic_maps(const TopicMaps& maps,
                                                    const std::filesystem::path& dir,
                                                    const cv::Mat& image = {});

/// `proprio mot maps`: the maps of one image.
struct TopicMapRun {
  std::filesystem::path lda_model;    ///< LDA model file (required)
  std::filesystem::path vocabulary;   ///< vocabulary file (required)
  std::filesystem::path image;        ///< the image (required)
  std::filesystem::path out;          ///< directory for topic_<i>.png (required)
  features::ExtractOptions features;  ///< how the image's features are extracted
  TopicMapOptions maps;

  void validate() const;
};

/// Reads the model, vocabulary and image, extracts the features, writes the maps (blended over
/// the image). Returns a line per topic: theta_i, the peak pixel and the file.
std::vector<std::string> run_topic_maps(const TopicMapRun& run);

}  // namespace proprio::recognition
