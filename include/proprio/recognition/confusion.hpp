#pragma once
// Confusion matrices of a classification (thesis Tables 6.1-6.5, 7.1-7.2): rows are the true
// classes, columns the predicted labels (classes or topics).
#include <span>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"

namespace proprio::recognition {

struct ConfusionMatrix {
  std::vector<std::string> rows;     ///< true classes
  std::vector<std::string> columns;  ///< predicted labels (classes, or topics z_1..z_K)
  /// counts[r][c]: documents of class r predicted as c.
  std::vector<std::vector<int>> counts;
  /// Documents of each class that got no prediction (an empty document: no features).
  std::vector<int> unclassified;

  [[nodiscard]] int row_total(int r) const;  ///< documents of class r, unclassified included
  [[nodiscard]] int total() const;
  /// Documents on the diagonal (meaningful when columns are the classes, in the same order).
  [[nodiscard]] int correct() const;
  /// correct() / total(); 0 for an empty matrix.
  [[nodiscard]] double accuracy() const;
  /// The mean over the classes (with documents) of the fraction of each class classified right:
  /// the "average accuracy of the matrix" of thesis Tables 6.4-6.5 and 7.1-7.2.
  [[nodiscard]] double mean_class_accuracy() const;
  /// A text table (counts; with `percent`, each row in percent of its class, as Tables 6.4-7.2).
  [[nodiscard]] std::string format(bool percent = false) const;
  /// {"rows", "columns", "counts", "unclassified", "accuracy", "mean_class_accuracy"}.
  [[nodiscard]] core::Json to_json() const;
};

/// Counts (truth[i], predicted[i]) pairs. truth in [0, rows); predicted in [0, columns) or -1
/// (unclassified). Asserts equal lengths and valid indices (programming errors).
ConfusionMatrix confusion_matrix(std::span<const int> truth, std::span<const int> predicted,
                                 std::vector<std::string> rows, std::vector<std::string> columns);

/// Column names z_1 .. z_K (the thesis numbers topics from 1).
std::vector<std::string> topic_names(int num_topics);

}  // namespace proprio::recognition
