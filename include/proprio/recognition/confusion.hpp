#pragma once
// Confusion matrices of a classification (thesis Tables 6.1-6.5, 7.1-7.2): rows are the true
// classes, columns the predicted labels (classes or topics).
#include <span>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
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
  /// {"rows", "columns", "counts", "unclassified", "accuracy", "mean_class_accuracy"}: its
  /// description's JSON.
  [[nodiscard]] core::Json to_json() const { return core::fields_to_json(*this); }

  /// Output only (accuracy and mean_class_accuracy are derived). A record that holds a matrix
  /// lists these fields flat (`ConfusionMatrix::describe(self.classes, v)`) or as a member.
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.rows, {"rows", "True classes"});
    v(self.columns, {"columns", "Predicted labels (classes, or topics z_1..z_K)"});
    v(self.counts, {"counts", "counts[r][c]: documents of class r predicted as c"});
    v(self.unclassified, {"unclassified", "Documents of each class with no prediction"});
    v(self.accuracy(), {"accuracy", "The diagonal's share of every document"});
    v(self.mean_class_accuracy(), {"mean_class_accuracy",
                                   "Mean over the classes of each's "
                                   "share classified right"});
  }
};

/// Counts (truth[i], predicted[i]) pairs. truth in [0, rows); predicted in [0, columns) or -1
/// (unclassified). Asserts equal lengths and valid indices (programming errors).
ConfusionMatrix confusion_matrix(std::span<const int> truth, std::span<const int> predicted,
                                 std::vector<std::string> rows, std::vector<std::string> columns);

/// Column names z_1 .. z_K (the thesis numbers topics from 1).
std::vector<std::string> topic_names(int num_topics);

}  // namespace proprio::recognition
