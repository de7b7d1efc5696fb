#pragma once
// Naming topics after objects (thesis 6.3.3, 7.3.1). LDA learns topics without labels; to read a
// confusion matrix against objects each topic must be given an object. The mapping uses labelled
// training views only, never the test labels: each topic goes to the object whose training
// views give it the highest mean proportion. Several topics may go to one object: that merges
// them, as the thesis merges z_2 and z_7 (Table 7.1) or z_1, z_2 and z_4 (Table 7.2).
#include <Eigen/Core>
#include <span>
#include <vector>

#include "proprio/core/fields.hpp"

namespace proprio::recognition {

struct TopicMapping {
  /// classes x K: mean E[theta] of each class's labelled views.
  Eigen::MatrixXd mean_theta;
  /// The class of each topic: argmax over classes of mean_theta's column (ties: lowest class).
  std::vector<int> topic_class;
  /// Classes that no topic went to (they can never be predicted).
  std::vector<int> orphan_classes;

  /// Output only: what an evaluation records of its mapping.
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.topic_class, {"topic_class", "The class of each topic"});
    v(core::matrix_rows(self.mean_theta), {"mean_theta", "Classes x K: mean E[theta]"});
  }
};

/// Maps the K topics to `num_classes` classes from the theta (D x K, rows E[theta_d]) of labelled
/// documents with labels in [0, num_classes). Rows with a negative label are ignored (empty
/// documents). Throws Error when a class has no labelled document (its mean would be undefined).
TopicMapping map_topics(const Eigen::MatrixXd& theta, std::span<const int> labels, int num_classes);

/// The class of each document: the class of its most probable topic (argmax_k theta_dk, thesis
/// 6.1.4, then the mapping; the merged columns of 7.3.1). -1 where `topic` is -1.
std::vector<int> mapped_classes(std::span<const int> topic, const TopicMapping& mapping);

}  // namespace proprio::recognition
