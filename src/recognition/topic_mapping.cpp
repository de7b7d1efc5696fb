#include "proprio/recognition/topic_mapping.hpp"

#include <cassert>
#include <string>

#include "proprio/core/error.hpp"

namespace proprio::recognition {

TopicMapping map_topics(const Eigen::MatrixXd& theta, std::span<const int> labels,
                        int num_classes) {
  assert(static_cast<std::size_t>(theta.rows()) == labels.size());
  assert(num_classes >= 1);
  const auto k_topics = theta.cols();
  TopicMapping m;
  m.mean_theta = Eigen::MatrixXd::Zero(num_classes, k_topics);
  std::vector<int> n(static_cast<std::size_t>(num_classes), 0);
  for (std::size_t d = 0; d < labels.size(); ++d) {
    const int c = labels[d];
    if (c < 0) continue;
    assert(c < num_classes);
    m.mean_theta.row(c) += theta.row(static_cast<Eigen::Index>(d));
    ++n[static_cast<std::size_t>(c)];
  }
  for (int c = 0; c < num_classes; ++c) {
    if (n[static_cast<std::size_t>(c)] == 0) {
      std::string msg = "class ";
      msg += std::to_string(c);
      msg += " has no labelled document with features to map topics with";
      throw Error(msg);
    }
    m.mean_theta.row(c) /= n[static_cast<std::size_t>(c)];
  }
  std::vector<bool> used(static_cast<std::size_t>(num_classes), false);
  for (Eigen::Index k = 0; k < k_topics; ++k) {
    Eigen::Index best = 0;
    m.mean_theta.col(k).maxCoeff(&best);  // first maximum on ties
    m.topic_class.push_back(static_cast<int>(best));
    used[static_cast<std::size_t>(best)] = true;
  }
  for (int c = 0; c < num_classes; ++c)
    if (!used[static_cast<std::size_t>(c)]) m.orphan_classes.push_back(c);
  return m;
}

std::vector<int> mapped_classes(std::span<const int> topic, const TopicMapping& mapping) {
  std::vector<int> out;
  out.reserve(topic.size());
  for (int t : topic) {
    assert(t < static_cast<int>(mapping.topic_class.size()));
    out.push_back(t < 0 ? -1 : mapping.topic_class[static_cast<std::size_t>(t)]);
  }
  return out;
}

}  // namespace proprio::recognition
