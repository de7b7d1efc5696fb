// Figures of the segmentation evaluation, drawn with OpenCV: P-R curves (thesis Figs 5-1, 5-2)
// and bar charts with standard-deviation error bars (Fig 5-3).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "proprio/core/error.hpp"
#include "proprio/eval/segmentation_eval.hpp"

namespace proprio::eval {
namespace fs = std::filesystem;
namespace {

const cv::Scalar kBlack(0, 0, 0), kGrey(200, 200, 200), kWhite(255, 255, 255);

cv::Scalar method_colour(std::size_t k) {
  static const cv::Scalar kColours[] = {{180, 119, 31}, {14, 127, 255},  {44, 160, 44},
                                        {40, 39, 214},  {189, 103, 148}, {75, 86, 140}};
  return kColours[k % 6];
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.5,
          const cv::Scalar& colour = kBlack, int thickness = 1) {
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thickness, cv::LINE_AA);
}

int text_width(const std::string& s, double scale = 0.5) {
  int base = 0;
  return cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base).width;
}

std::string fmt(const char* f, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

struct Curve {
  std::string name;
  cv::Scalar colour;
  GroupSummary g;
};

// One P-R panel, 400 x 400: recall on x, precision on y, the point closest to (1, 1) ringed.
cv::Mat pr_panel(const std::string& title, const std::vector<Curve>& curves) {
  cv::Mat img(400, 400, CV_8UC3, kWhite);
  const cv::Rect plot(55, 40, 320, 300);
  auto to_px = [&](double recall, double precision) {
    return cv::Point(plot.x + static_cast<int>(std::lround(recall * plot.width)),
                     plot.y + plot.height - static_cast<int>(std::lround(precision * plot.height)));
  };
  for (int k = 0; k <= 5; ++k) {
    const double v = k / 5.0;
    cv::line(img, to_px(v, 0), to_px(v, 1), kGrey);
    cv::line(img, to_px(0, v), to_px(1, v), kGrey);
    text(img, fmt("%.1f", v), to_px(v, 0) + cv::Point(-10, 18), 0.4);
    text(img, fmt("%.1f", v), to_px(0, v) + cv::Point(-32, 5), 0.4);
  }
  cv::rectangle(img, plot, kBlack);
  text(img, "recall", {plot.x + plot.width / 2 - 20, 392}, 0.45);
  text(img, "precision", {2, 28}, 0.45);
  text(img, title, {plot.x + plot.width / 2 - text_width(title, 0.55) / 2, 22}, 0.55, kBlack, 1);
  int legend_y = plot.y + plot.height - 10 - 18 * static_cast<int>(curves.size());
  for (const Curve& c : curves) {
    if (c.g.episodes == 0) continue;
    std::vector<cv::Point> pts;
    for (std::size_t k = 0; k < c.g.pr_recall.size(); ++k) {
      pts.push_back(to_px(c.g.pr_recall[k], c.g.pr_precision[k]));
    }
    cv::polylines(img, pts, false, c.colour, 2, cv::LINE_AA);
    for (const auto& p : pts) cv::circle(img, p, 3, c.colour, cv::FILLED, cv::LINE_AA);
    if (c.g.pr_best >= 0) {
      cv::circle(img, pts[static_cast<std::size_t>(c.g.pr_best)], 7, c.colour, 2, cv::LINE_AA);
    }
  }
  for (const Curve& c : curves) {
    cv::line(img, {plot.x + 10, legend_y - 4}, {plot.x + 30, legend_y - 4}, c.colour, 3);
    text(img, c.name + " (" + std::to_string(c.g.episodes) + ")", {plot.x + 36, legend_y}, 0.42);
    legend_y += 18;
  }
  return img;
}

cv::Mat row_of(const std::vector<cv::Mat>& panels) {
  cv::Mat out;
  cv::hconcat(panels, out);
  return out;
}

// Grouped bars: one group per label, one bar per method, error bars of one standard deviation.
cv::Mat bar_chart(const std::string& title, const std::string& ylabel,
                  const std::vector<std::string>& labels, const std::vector<std::string>& methods,
                  const std::vector<std::vector<double>>& means,
                  const std::vector<std::vector<double>>& stds, double ymax) {
  const int group_w = 30 + 26 * static_cast<int>(methods.size());
  const int width = std::max(500, 90 + group_w * static_cast<int>(labels.size()) + 20);
  cv::Mat img(420, width, CV_8UC3, kWhite);
  const cv::Rect plot(70, 50, width - 90, 290);
  auto y_px = [&](double v) {
    return plot.y + plot.height -
           static_cast<int>(std::lround(std::clamp(v / ymax, 0.0, 1.0) * plot.height));
  };
  for (int k = 0; k <= 5; ++k) {
    const double v = ymax * k / 5.0;
    cv::line(img, {plot.x, y_px(v)}, {plot.x + plot.width, y_px(v)}, kGrey);
    text(img, fmt("%.2f", v), {plot.x - 45, y_px(v) + 5}, 0.4);
  }
  cv::rectangle(img, plot, kBlack);
  text(img, title, {plot.x, 22}, 0.55);
  text(img, ylabel, {plot.x, 42}, 0.42);
  for (std::size_t g = 0; g < labels.size(); ++g) {
    const int x0 = plot.x + 20 + static_cast<int>(g) * group_w;
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const int x = x0 + 26 * static_cast<int>(m);
      const double v = means[m][g];
      if (std::isnan(v)) continue;
      cv::rectangle(img, cv::Point(x, y_px(v)), cv::Point(x + 20, y_px(0)), method_colour(m),
                    cv::FILLED);
      const double s = stds[m][g];
      const int cx = x + 10;
      cv::line(img, {cx, y_px(v - s)}, {cx, y_px(v + s)}, kBlack, 1);
      cv::line(img, {cx - 4, y_px(v + s)}, {cx + 4, y_px(v + s)}, kBlack, 1);
      cv::line(img, {cx - 4, y_px(v - s)}, {cx + 4, y_px(v - s)}, kBlack, 1);
    }
    const std::string& l = labels[g];
    text(img, l, {x0 + (26 * static_cast<int>(methods.size()) - text_width(l, 0.4)) / 2, 360}, 0.4);
  }
  int lx = plot.x;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    cv::rectangle(img, cv::Rect(lx, 390, 14, 14), method_colour(m), cv::FILLED);
    text(img, methods[m], {lx + 18, 402}, 0.42);
    lx += 30 + text_width(methods[m], 0.42);
  }
  return img;
}

void save(const fs::path& file, const cv::Mat& img) {
  if (!cv::imwrite(file.string(), img)) throw Error::in_file(file, "cannot write the image");
}

}  // namespace

std::vector<std::string> write_plots(const fs::path& dir,
                                     const std::vector<EpisodeEvaluation>& episodes,
                                     const std::vector<Method>& methods,
                                     const EvalOptions& options) {
  std::set<std::string> object_set;
  for (const auto& e : episodes) object_set.insert(e.object.empty() ? "(none)" : e.object);
  const std::vector<std::string> objects(object_set.begin(), object_set.end());
  auto sweep_of = [&](std::size_t k) {
    return methods[k] == Method::kFm ? options.threshold_sweep : options.fraction_sweep;
  };
  auto group = [&](std::size_t k, const std::string& background, const std::string& object) {
    return summarise(episodes, k, sweep_of(k), options, background,
                     object == "(none)" ? std::string() : object);
  };
  auto curves = [&](const std::string& background, const std::string& object) {
    std::vector<Curve> c;
    for (std::size_t k = 0; k < methods.size(); ++k) {
      c.push_back({to_string(methods[k]), method_colour(k), group(k, background, object)});
    }
    return c;
  };
  std::vector<std::string> files;
  save(dir / "pr_by_background.png",
       row_of({pr_panel("static background", curves("static", kAnyGroup)),
               pr_panel("moving background", curves("moving", kAnyGroup)),
               pr_panel("all episodes", curves(kAnyGroup, kAnyGroup))}));
  files.push_back("pr_by_background.png");
  {
    std::vector<cv::Mat> panels;
    panels.reserve(objects.size());
    for (const auto& o : objects) panels.push_back(pr_panel(o, curves(kAnyGroup, o)));
    // Rows of at most four panels.
    std::vector<cv::Mat> rows;
    for (std::size_t i = 0; i < panels.size(); i += 4) {
      std::vector<cv::Mat> row(panels.begin() + static_cast<long>(i),
                               panels.begin() + static_cast<long>(std::min(i + 4, panels.size())));
      while (row.size() < std::min<std::size_t>(4, panels.size())) {
        row.push_back(cv::Mat(400, 400, CV_8UC3, kWhite));
      }
      rows.push_back(row_of(row));
    }
    cv::Mat all;
    cv::vconcat(rows, all);
    save(dir / "pr_by_object.png", all);
    files.push_back("pr_by_object.png");
  }
  std::vector<std::string> labels = objects;
  labels.push_back("static");
  labels.push_back("moving");
  std::vector<std::string> names;
  std::vector<std::vector<double>> jm, js, lm, ls;
  double lmax = 0.0;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    names.push_back(to_string(methods[k]));
    std::vector<double> a, b, c, d;
    for (const auto& l : labels) {
      const bool bg = l == "static" || l == "moving";
      const GroupSummary g = group(k, bg ? l : kAnyGroup, bg ? kAnyGroup : l);
      const double nan = std::nan("");
      a.push_back(g.episodes ? g.mean_jaccard : nan);
      b.push_back(g.std_jaccard);
      c.push_back(g.episodes ? g.mean_l2 : nan);
      d.push_back(g.std_l2);
      if (g.episodes) lmax = std::max(lmax, g.mean_l2 + g.std_l2);
    }
    jm.push_back(a);
    js.push_back(b);
    lm.push_back(c);
    ls.push_back(d);
  }
  save(dir / "bars_jaccard.png",
       bar_chart("Jaccard index at the scored frame, by object and background",
                 "mean (1 = perfect), error bars: 1 std", labels, names, jm, js, 1.0));
  files.push_back("bars_jaccard.png");
  lmax = lmax > 0 ? std::ceil(lmax * 10.0) / 10.0 : 1.0;
  save(dir / "bars_l2.png",
       bar_chart("L2 distance (RMS pixel difference) at the scored frame",
                 "mean (0 = perfect), error bars: 1 std", labels, names, lm, ls, lmax));
  files.push_back("bars_l2.png");
  return files;
}

}  // namespace proprio::eval
