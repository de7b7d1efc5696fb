#include "proprio/recognition/confusion.hpp"

#include <algorithm>
#include <cassert>
#include <cstdio>
#include <numeric>

namespace proprio::recognition {

int ConfusionMatrix::row_total(int r) const {
  const auto& row = counts.at(static_cast<std::size_t>(r));
  return std::accumulate(row.begin(), row.end(), 0) + unclassified.at(static_cast<std::size_t>(r));
}

int ConfusionMatrix::total() const {
  int t = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) t += row_total(static_cast<int>(r));
  return t;
}

int ConfusionMatrix::correct() const {
  int c = 0;
  for (std::size_t r = 0; r < rows.size() && r < columns.size(); ++r) c += counts[r][r];
  return c;
}

double ConfusionMatrix::accuracy() const {
  const int t = total();
  return t > 0 ? static_cast<double>(correct()) / t : 0.0;
}

double ConfusionMatrix::mean_class_accuracy() const {
  double sum = 0;
  int classes = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int t = row_total(static_cast<int>(r));
    if (t == 0) continue;
    ++classes;
    if (r < columns.size()) sum += static_cast<double>(counts[r][r]) / t;
  }
  return classes > 0 ? sum / classes : 0.0;
}

std::string ConfusionMatrix::format(bool percent) const {
  std::size_t width = 6;
  for (const auto& s : rows) width = std::max(width, s.size() + 1);
  std::size_t cell = 6;
  for (const auto& s : columns) cell = std::max(cell, s.size() + 1);
  const bool any_unclassified =
      std::any_of(unclassified.begin(), unclassified.end(), [](int u) { return u > 0; });
  std::string out(width, ' ');
  auto pad = [](const std::string& s, std::size_t w) {
    return s.size() >= w ? s : std::string(w - s.size(), ' ') + s;
  };
  for (const auto& c : columns) out += pad(c, cell);
  if (any_unclassified) out += pad("none", cell);
  out += '\n';
  char buf[32];
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::string line = rows[r];
    line.resize(width, ' ');
    const int t = row_total(static_cast<int>(r));
    auto value = [&](int n) {
      if (percent) {
        std::snprintf(buf, sizeof buf, "%.0f", t > 0 ? 100.0 * n / t : 0.0);
      } else {
        std::snprintf(buf, sizeof buf, "%d", n);
      }
      return std::string(buf);
    };
    for (int n : counts[r]) line += pad(value(n), cell);
    if (any_unclassified) line += pad(value(unclassified[r]), cell);
    out += line;
    out += '\n';
  }
  return out;
}

ConfusionMatrix confusion_matrix(std::span<const int> truth, std::span<const int> predicted,
                                 std::vector<std::string> rows, std::vector<std::string> columns) {
  assert(truth.size() == predicted.size());
  ConfusionMatrix m;
  m.counts.assign(rows.size(), std::vector<int>(columns.size(), 0));
  m.unclassified.assign(rows.size(), 0);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const int t = truth[i];
    const int p = predicted[i];
    assert(t >= 0 && static_cast<std::size_t>(t) < rows.size());
    assert(p >= -1 && p < static_cast<int>(columns.size()));
    if (p < 0) {
      ++m.unclassified[static_cast<std::size_t>(t)];
    } else {
      ++m.counts[static_cast<std::size_t>(t)][static_cast<std::size_t>(p)];
    }
  }
  m.rows = std::move(rows);
  m.columns = std::move(columns);
  return m;
}

std::vector<std::string> topic_names(int num_topics) {
  std::vector<std::string> names;
  for (int k = 1; k <= num_topics; ++k) names.push_back("z_" + std::to_string(k));
  return names;
}

}  // namespace proprio::recognition
