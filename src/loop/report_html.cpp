#include "report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "proprio/core/text.hpp"

namespace proprio::loop::report {

namespace {

double clean(double v) { return std::isfinite(v) && v > 0 ? v : 0.0; }

}  // namespace

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "\xE2\x80\x93";
  std::string s = core::printf_string("%.*f", digits, v);
  if (s.rfind("-0", 0) == 0 && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

std::string percent(double fraction) {
  if (!std::isfinite(fraction)) return "\xE2\x80\x93";
  return fixed(100.0 * fraction, 1) + "%";
}

std::string horizontal_bars(const std::vector<Bar>& bars, double max_value, std::string_view title,
                            std::string_view colour, int width) {
  double top = max_value;
  if (!(top > 0) || !std::isfinite(top)) {
    top = 0;
    for (const Bar& b : bars) top = std::max({top, clean(b.value), clean(b.high)});
  }
  if (!(top > 0)) top = 1;
  const int row = 22;
  const int label_w = 150;
  std::size_t longest = 0;
  for (const Bar& b : bars) longest = std::max(longest, b.text.size());
  const int text_w = std::clamp(static_cast<int>(longest) * 7 + 8, 60, width / 2);
  const int bar_w = std::max(60, width - label_w - text_w);
  const int height = row * static_cast<int>(bars.size()) + 6;
  std::string s = core::printf_string(
      "<svg class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
      "viewBox=\"0 0 %d %d\" role=\"img\"><title>",
      width, height, width, height);
  s += escape(title);
  s += "</title>";
  for (std::size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const int y = 3 + row * static_cast<int>(i);
    const double w = bar_w * std::min(1.0, clean(b.value) / top);
    s += core::printf_string("<text x=\"%d\" y=\"%d\" text-anchor=\"end\" font-size=\"12\">",
                             label_w - 6, y + 15);
    s += escape(b.label);
    s += core::printf_string("</text><rect x=\"%d\" y=\"%d\" width=\"%.1f\" height=\"%d\" fill=\"",
                             label_w, y + 3, w, row - 8);
    s += escape(colour);
    s += "\"/>";
    if (b.low >= 0 && b.high >= b.low && std::isfinite(b.high)) {
      const double x0 = label_w + bar_w * std::min(1.0, b.low / top);
      const double x1 = label_w + bar_w * std::min(1.0, b.high / top);
      const int ym = y + row / 2 - 1;
      s += core::printf_string(
          "<path d=\"M%.1f %dH%.1fM%.1f %dv8M%.1f %dv8\" stroke=\"#222\" stroke-width=\"1.5\" "
          "fill=\"none\"/>",
          x0, ym, x1, x0, ym - 4, x1, ym - 4);
    }
    s += core::printf_string("<text x=\"%d\" y=\"%d\" font-size=\"12\">", label_w + bar_w + 6,
                             y + 15);
    s += escape(b.text);
    s += "</text>";
  }
  s += "</svg>";
  return s;
}

std::string vertical_bars(const std::vector<Bar>& bars, double max_value, std::string_view title,
                          std::string_view x_label, std::string_view colour, int width,
                          int height) {
  double top = max_value;
  if (!(top > 0) || !std::isfinite(top)) {
    top = 0;
    for (const Bar& b : bars) top = std::max(top, clean(b.value));
  }
  if (!(top > 0)) top = 1;
  const int left = 44;
  const int bottom = 34;
  const int plot_w = width - left - 8;
  const int plot_h = height - bottom - 8;
  const double slot = bars.empty() ? plot_w : static_cast<double>(plot_w) / bars.size();
  std::string s = core::printf_string(
      "<svg class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
      "viewBox=\"0 0 %d %d\" role=\"img\"><title>",
      width, height, width, height);
  s += escape(title);
  s += "</title>";
  // Axes and the top value.
  s += core::printf_string(
      "<path d=\"M%d 8V%dH%d\" stroke=\"#888\" fill=\"none\"/><text x=\"%d\" y=\"16\" "
      "text-anchor=\"end\" font-size=\"10\">",
      left, 8 + plot_h, left + plot_w, left - 4);
  s += escape(fixed(top, top >= 10 ? 0 : (top >= 0.1 ? 2 : 3)));
  s += core::printf_string(
      "</text><text x=\"%d\" y=\"%d\" text-anchor=\"end\" font-size=\"10\">0</text>", left - 4,
      8 + plot_h);
  const bool labelled = bars.size() <= 30;
  for (std::size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const double h = plot_h * std::min(1.0, clean(b.value) / top);
    const double x = left + slot * static_cast<double>(i) + (labelled ? slot * 0.15 : 0);
    const double w = std::max(0.5, labelled ? slot * 0.7 : slot);
    s += core::printf_string("<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"",
                             x, 8 + plot_h - h, w, h);
    s += escape(colour);
    s += "\"><title>";
    s += escape(b.label);
    s += ": ";
    s += escape(b.text);
    s += "</title></rect>";
    if (labelled) {
      s += core::printf_string("<text x=\"%.2f\" y=\"%d\" text-anchor=\"middle\" font-size=\"10\">",
                               left + slot * (static_cast<double>(i) + 0.5), 8 + plot_h + 12);
      s += escape(b.label);
      s += "</text>";
    }
  }
  s += core::printf_string("<text x=\"%d\" y=\"%d\" text-anchor=\"middle\" font-size=\"11\">",
                           left + plot_w / 2, height - 4);
  s += escape(x_label);
  s += "</text></svg>";
  return s;
}

std::string colour_bar(const std::vector<std::string>& stops, std::string_view low,
                       std::string_view high, int width) {
  std::string s = core::printf_string(
      "<svg class=\"colourbar\" xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"30\" "
      "viewBox=\"0 0 %d 30\" role=\"img\"><title>colour scale</title><defs><linearGradient "
      "id=\"cb\">",
      width + 60, width + 60);
  for (std::size_t i = 0; i < stops.size(); ++i) {
    const double at = stops.size() > 1 ? 100.0 * static_cast<double>(i) / (stops.size() - 1) : 0;
    s += core::printf_string("<stop offset=\"%.1f%%\" stop-color=\"", at);
    s += escape(stops[i]);
    s += "\"/>";
  }
  s += "</linearGradient></defs><text x=\"0\" y=\"14\" font-size=\"11\">";
  s += escape(low);
  s += core::printf_string(
      "</text><rect x=\"28\" y=\"3\" width=\"%d\" height=\"14\" fill=\"url(#cb)\"/><text x=\"%d\" "
      "y=\"14\" font-size=\"11\">",
      width, width + 32);
  s += escape(high);
  s += "</text></svg>";
  return s;
}

std::string cell_shade(double fraction) {
  const double f = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
  return core::printf_string("rgba(59,117,175,%.3f)", 0.08 + 0.8 * f);
}

Interval wilson_interval(int k, int n) {
  if (n <= 0) return {};
  const double z = 1.959963984540054;
  const double p = static_cast<double>(k) / n;
  const double z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4.0 * n)) / (1 + z2n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace proprio::loop::report
