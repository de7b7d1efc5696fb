#pragma once
// Private helpers of the learn report (learn_report.cpp): HTML escaping, numbers that are never
// NaN/Inf on the page, and charts as inline SVG.

#include <string>
#include <string_view>
#include <vector>

#include "proprio/core/text.hpp"

namespace proprio::loop::report {

/// `text` escaped for HTML text and attribute values (core::markup_escape).
inline std::string escape(std::string_view text) { return core::markup_escape(text); }

/// A number with `digits` decimals; "–" when not finite (never "nan" or "inf" on the page).
std::string fixed(double v, int digits);
/// A fraction as a percentage with one decimal ("87.5%"); "–" when not finite.
std::string percent(double fraction);

/// One bar of a chart.
struct Bar {
  std::string label;  ///< shown beside the bar (escaped when drawn)
  double value = 0;   ///< non-finite or negative values are drawn as 0
  std::string text;   ///< the value as written beside the bar (escaped when drawn)
  double low = -1;    ///< an interval drawn as a whisker when 0 <= low <= high
  double high = -1;
};

/// Horizontal bars, one row each, scaled to `max_value` (<= 0: the largest value). `title` is
/// the chart's accessible title.
std::string horizontal_bars(const std::vector<Bar>& bars, double max_value, std::string_view title,
                            std::string_view colour = "#3b75af", int width = 560);

/// Vertical bars (a histogram), no per-bar text when there are more than 30; `x_label` names the
/// axis.
std::string vertical_bars(const std::vector<Bar>& bars, double max_value, std::string_view title,
                          std::string_view x_label, std::string_view colour = "#3b75af",
                          int width = 360, int height = 150);

/// A horizontal colour bar from `stops` ("#rrggbb", low to high) labelled `low` and `high`.
std::string colour_bar(const std::vector<std::string>& stops, std::string_view low,
                       std::string_view high, int width = 200);

/// "rgba(r,g,b,a)" of the cell shading of a confusion matrix for a fraction in [0, 1].
std::string cell_shade(double fraction);

/// The Wilson 95% interval of k successes in n trials; [0, 1] for n = 0.
struct Interval {
  double low = 0;
  double high = 1;
};
Interval wilson_interval(int k, int n);

}  // namespace proprio::loop::report
