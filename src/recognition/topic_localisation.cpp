#include "proprio/recognition/topic_localisation.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/geometry/image_file.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::recognition {

void TopicMapOptions::validate() const {
  core::check_field_bounds(*this, "topic maps");
  inference.validate();
}

TopicMaps topic_maps(const features::Features& f, cv::Size image_size,
                     const topics::LdaModel& model, const features::Vocabulary& vocabulary,
                     const TopicMapOptions& options) {
  options.validate();
  if (model.num_words() != vocabulary.size()) {
    throw Error("topic maps: the LDA model has " + std::to_string(model.num_words()) +
                " words but the vocabulary " + std::to_string(vocabulary.size()));
  }
  require(image_size.width > 0 && image_size.height > 0, "topic maps: an empty image");
  const int k_topics = model.num_topics();
  const std::vector<std::int32_t> words =
      f.empty() ? std::vector<std::int32_t>{} : features::bag_of_words(vocabulary, f.descriptors);
  topics::Corpus doc(vocabulary.size());
  doc.add_tokens(words);
  TopicMaps out;
  out.theta = topics::infer_topics(model, doc, options.inference).theta().row(0).transpose();
  const Eigen::MatrixXd beta = model.topic_word();
  for (int i = 0; i < k_topics; ++i) {
    out.density.emplace_back(image_size, CV_64F, cv::Scalar(0));
  }
  for (std::size_t k = 0; k < words.size(); ++k) {
    const cv::Point2f& p = f.keypoints[k].pt;
    const int x = std::clamp(cvRound(p.x), 0, image_size.width - 1);
    const int y = std::clamp(cvRound(p.y), 0, image_size.height - 1);
    const Eigen::VectorXd b = beta.col(words[k]);
    double norm = 1.0;
    if (options.weight == MapWeight::kResponsibility) norm = out.theta.dot(b);
    for (int i = 0; i < k_topics; ++i) {
      const double w = options.weight == MapWeight::kResponsibility && norm > 0
                           ? out.theta(i) * b(i) / norm
                           : b(i);
      out.density[static_cast<std::size_t>(i)].at<double>(y, x) += w;
    }
  }
  for (auto& m : out.density) {
    cv::GaussianBlur(m, m, cv::Size(0, 0), options.sigma, options.sigma, cv::BORDER_CONSTANT);
    const double total = cv::sum(m)[0];
    cv::Point peak(-1, -1);
    if (total > 0 && std::isfinite(total)) {
      m /= total;
      double mx = 0;
      cv::minMaxLoc(m, nullptr, &mx, nullptr, &peak);
    } else {
      m.setTo(0);
    }
    out.peak.push_back(peak);
  }
  return out;
}

cv::Mat topic_map_image(const cv::Mat& density, const cv::Mat& over) {
  double mx = 0;
  cv::minMaxLoc(density, nullptr, &mx);
  cv::Mat grey;
  density.convertTo(grey, CV_8U, mx > 0 ? 255.0 / mx : 0.0);
  cv::Mat colour;
  cv::applyColorMap(grey, colour, cv::COLORMAP_JET);
  if (over.empty()) return colour;
  require(over.size() == density.size(), "topic_map_image: the image is not the map's size");
  cv::Mat base = over;
  if (base.channels() == 1) cv::cvtColor(over, base, cv::COLOR_GRAY2BGR);
  cv::Mat blended;
  cv::addWeighted(base, 0.5, colour, 0.5, 0.0, blended);
  return blended;
}

std::vector<std::filesystem::path> write_topic_maps(const TopicMaps& maps,
                                                    const std::filesystem::path& dir,
                                                    const cv::Mat& image) {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> written;
  for (std::size_t i = 0; i < maps.density.size(); ++i) {
    const auto path = dir / ("topic_" + std::to_string(i + 1) + ".png");
    if (!cv::imwrite(path.string(), topic_map_image(maps.density[i], image))) {
      throw Error::in_file(path, "could not write the topic map");
    }
    written.push_back(path);
  }
  return written;
}

void TopicMapRun::validate() const {
  if (lda_model.empty() || vocabulary.empty() || image.empty() || out.empty()) {
    throw Error("mot maps: the LDA model, the vocabulary, the image and the output are required");
  }
  features.validate();
  maps.validate();
}

std::vector<std::string> run_topic_maps(const TopicMapRun& run) {
  run.validate();
  const topics::LdaModel model = topics::load_lda_model(run.lda_model);
  const features::Vocabulary vocabulary = features::read_vocabulary(run.vocabulary);
  const cv::Mat image = geometry::read_image(run.image, cv::IMREAD_COLOR);
  const features::Features f = features::extract_file_features(run.image, image, run.features);
  const TopicMaps maps = topic_maps(f, image.size(), model, vocabulary, run.maps);
  const auto files = write_topic_maps(maps, run.out, image);
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < files.size(); ++i) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "z_%zu: theta %.3f, peak (%d, %d): ", i + 1,
                  maps.theta(static_cast<Eigen::Index>(i)), maps.peak[i].x, maps.peak[i].y);
    lines.push_back(buf + files[i].string());
  }
  return lines;
}

}  // namespace proprio::recognition
