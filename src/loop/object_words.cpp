// Object words (thesis 8.1.2) and top-down recognition (8.1.3): see the header.
#include "proprio/loop/object_words.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/topics/dirichlet_fit.hpp"

namespace proprio::loop {

namespace {

constexpr double kFloor = 1e-12;
constexpr int kMaxMeanShiftRows = 3000;  // mean shift runs over a seeded sample of at most these
constexpr int kMeanShiftIterations = 30;

// Squared distances between the rows of a (n x D) and b (k x D): n x k.
Eigen::MatrixXd sq_distances(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const Eigen::VectorXd an = a.rowwise().squaredNorm();
  const Eigen::VectorXd bn = b.rowwise().squaredNorm();
  Eigen::MatrixXd d = -2.0 * a * b.transpose();
  d.colwise() += an;
  d.rowwise() += bn.transpose();
  return d.cwiseMax(0.0);
}

Eigen::MatrixXd stack(const std::vector<Eigen::MatrixXd>& frames) {
  Eigen::Index n = 0;
  Eigen::Index cols = 0;
  for (const auto& f : frames) {
    n += f.rows();
    if (f.rows() > 0) cols = f.cols();
  }
  Eigen::MatrixXd x(n, cols);
  Eigen::Index r = 0;
  for (const auto& f : frames) {
    if (f.rows() == 0) continue;
    x.middleRows(r, f.rows()) = f;
    r += f.rows();
  }
  return x;
}

std::optional<topics::Dirichlet> fit(const topics::DirichletStats& s) {
  if (s.count() < 2) return std::nullopt;
  return topics::fit_dirichlet(s).dirichlet;
}

}  // namespace

void ObjectWordOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0)) {
      throw Error(std::string("object words: ") + name + " must be positive");
    }
  };
  positive(bandwidth, "bandwidth");
  positive(sigma2, "sigma2");
  positive(density_sigma, "density_sigma");
  if (max_words < 2) throw Error("object words: max_words must be at least 2");
  if (mean_shift_seeds < 2) throw Error("object words: mean_shift_seeds must be at least 2");
  if (min_features < 1) throw Error("object words: min_features must be at least 1");
  if (thresholds.empty()) throw Error("object words: no thresholds");
  for (double t : thresholds) {
    if (!(t > 0 && t < 1)) throw Error("object words: thresholds must be in (0, 1)");
  }
}

Eigen::MatrixXd unit_descriptors(const cv::Mat& descriptors) {
  Eigen::MatrixXd x(descriptors.rows, descriptors.cols);
  for (int r = 0; r < descriptors.rows; ++r) {
    const auto* p = descriptors.ptr<float>(r);
    double n2 = 0;
    for (int c = 0; c < descriptors.cols; ++c) n2 += static_cast<double>(p[c]) * p[c];
    const double s = n2 > 0 ? 1.0 / std::sqrt(n2) : 0.0;
    for (int c = 0; c < descriptors.cols; ++c) x(r, c) = p[c] * s;
  }
  return x;
}

Eigen::MatrixXd mean_shift_words(const Eigen::MatrixXd& x_all, const ObjectWordOptions& options,
                                 core::Rng& rng) {
  if (x_all.rows() == 0) return {};
  // A seeded sample of the rows keeps the cost bounded.
  Eigen::MatrixXd x = x_all;
  if (x_all.rows() > kMaxMeanShiftRows) {
    x.resize(kMaxMeanShiftRows, x_all.cols());
    for (int r = 0; r < kMaxMeanShiftRows; ++r) {
      x.row(r) =
          x_all.row(static_cast<Eigen::Index>(rng.index(static_cast<std::uint64_t>(x_all.rows()))));
    }
  }
  const int s = std::min<int>(options.mean_shift_seeds, static_cast<int>(x.rows()));
  Eigen::MatrixXd m(s, x.cols());
  for (int i = 0; i < s; ++i) {
    m.row(i) = x.row(static_cast<Eigen::Index>(rng.index(static_cast<std::uint64_t>(x.rows()))));
  }
  const double h2 = options.bandwidth * options.bandwidth;
  for (int it = 0; it < kMeanShiftIterations; ++it) {
    const Eigen::MatrixXd k = (-sq_distances(m, x) / (2 * h2)).array().exp().matrix();
    Eigen::MatrixXd next = k * x;
    const Eigen::VectorXd w = k.rowwise().sum();
    for (int i = 0; i < s; ++i) {
      if (w(i) > 0)
        next.row(i) /= w(i);
      else
        next.row(i) = m.row(i);
    }
    const double change = (next - m).rowwise().norm().maxCoeff();
    m = next;
    if (change < 1e-4 * options.bandwidth) break;
  }
  // Merge modes closer than bandwidth / 2; support = starts that reached each.
  std::vector<Eigen::VectorXd> modes;
  std::vector<int> support;
  for (int i = 0; i < s; ++i) {
    bool merged = false;
    for (std::size_t j = 0; j < modes.size() && !merged; ++j) {
      if ((modes[j] - m.row(i).transpose()).norm() < options.bandwidth / 2) {
        ++support[j];
        merged = true;
      }
    }
    if (!merged) {
      modes.emplace_back(m.row(i).transpose());
      support.push_back(1);
    }
  }
  std::vector<std::size_t> order(modes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return support[a] > support[b]; });
  const auto k = std::min<std::size_t>(order.size(), static_cast<std::size_t>(options.max_words));
  Eigen::MatrixXd words(static_cast<Eigen::Index>(k), x.cols());
  for (std::size_t i = 0; i < k; ++i) words.row(static_cast<Eigen::Index>(i)) = modes[order[i]];
  return words;
}

Eigen::VectorXd frame_word_distribution(const Eigen::MatrixXd& words, const Eigen::MatrixXd& x,
                                        double sigma2) {
  Eigen::VectorXd p = Eigen::VectorXd::Constant(words.rows(), kFloor);
  if (x.rows() > 0 && words.rows() > 0) {
    const Eigen::MatrixXd k = (-sq_distances(words, x) / (2 * sigma2)).array().exp().matrix();
    p += k.rowwise().sum() / static_cast<double>(x.rows());
  }
  return p / p.sum();
}

topics::DirichletStats ObjectModel::frame_stats(const std::vector<Eigen::MatrixXd>& frames,
                                                const ObjectWordOptions& options) const {
  topics::DirichletStats s(num_words());
  for (const auto& f : frames) {
    if (f.rows() == 0) continue;
    s.add_log(frame_word_distribution(words_, f, options.sigma2).array().log().matrix());
  }
  return s;
}

bool ObjectModel::first_push(const std::vector<Eigen::MatrixXd>& frames,
                             const ObjectWordOptions& options, core::Rng& rng) {
  int used = 0;
  for (const auto& f : frames) used += f.rows() > 0 ? 1 : 0;
  if (used < 2) return false;
  Eigen::MatrixXd w = mean_shift_words(stack(frames), options, rng);
  if (w.rows() < 2) return false;
  words_ = std::move(w);
  counts_.assign(static_cast<std::size_t>(words_.rows()), 1.0);
  stats_ = frame_stats(frames, options);
  exact_ = fit(stats_);
  fifty_ = exact_;
  dirichlet_ = exact_;
  return dirichlet_.has_value();
}

void ObjectModel::later_push(const std::vector<Eigen::MatrixXd>& frames,
                             const ObjectWordOptions& options, core::Rng& rng) {
  if (!learned()) {
    (void)first_push(frames, options, rng);
    return;
  }
  const Eigen::MatrixXd x = stack(frames);
  if (x.rows() == 0) return;
  // Every word toward its nearest new descriptor: w <- (N w + d) / (N + 1).
  const Eigen::MatrixXd d = sq_distances(words_, x);
  for (Eigen::Index j = 0; j < words_.rows(); ++j) {
    Eigen::Index best = 0;
    d.row(j).minCoeff(&best);
    double& n = counts_[static_cast<std::size_t>(j)];
    words_.row(j) = (n * words_.row(j) + x.row(best)) / (n + 1);
    n += 1;
  }
  const topics::DirichletStats fresh = frame_stats(frames, options);
  if (fresh.count() == 0) return;
  stats_.merge(fresh);
  exact_ = fit(stats_);
  if (fifty_) {
    const Eigen::MatrixXd old = fifty_->sample_log(rng, static_cast<int>(fresh.count()));
    topics::DirichletStats s = topics::DirichletStats::of_log_proportions(old);
    s.merge(fresh);
    fifty_ = fit(s);
  } else {
    fifty_ = exact_;
  }
  dirichlet_ = options.update == DirichletUpdate::kExact ? exact_ : fifty_;
}

std::optional<std::pair<double, double>> ObjectModel::predictive_log_likelihood(
    const std::vector<Eigen::MatrixXd>& frames, const ObjectWordOptions& options) const {
  if (!exact_ || !fifty_) return std::nullopt;
  double a = 0;
  double b = 0;
  int n = 0;
  for (const auto& f : frames) {
    if (f.rows() == 0) continue;
    const Eigen::VectorXd lp =
        frame_word_distribution(words_, f, options.sigma2).array().log().matrix();
    a += exact_->log_density_of_log(lp);
    b += fifty_->log_density_of_log(lp);
    ++n;
  }
  if (n == 0 || !std::isfinite(a) || !std::isfinite(b)) return std::nullopt;
  return std::make_pair(a / n, b / n);
}

Eigen::VectorXd ObjectModel::log_p_descriptors(const Eigen::MatrixXd& x,
                                               const ObjectWordOptions& options) const {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(x.rows(), -std::numeric_limits<double>::max());
  if (!learned() || x.rows() == 0) return out;
  const Eigen::VectorXd logw = dirichlet_->mean().array().log().matrix();
  const Eigen::MatrixXd e = -sq_distances(x, words_) / (2 * options.sigma2);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Eigen::VectorXd t = e.row(i).transpose() + logw;
    const double mx = t.maxCoeff();
    out(i) = mx + std::log((t.array() - mx).exp().sum());
  }
  return out;
}

TopDownResult recognise_top_down(const ObjectModel& model, const std::vector<cv::Point2f>& points,
                                 const Eigen::MatrixXd& x, cv::Size size,
                                 const ObjectWordOptions& options) {
  TopDownResult r;
  if (!model.learned()) {
    r.message = "no model yet";
    return r;
  }
  if (x.rows() == 0 || points.empty()) {
    r.message = "no features in the look";
    return r;
  }
  // p(d) (8.4) splatted at the features and blurred: p(x) (8.5).
  const Eigen::VectorXd lp = model.log_p_descriptors(x, options);
  cv::Mat1f px(size, 0.0F);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int u = std::clamp(static_cast<int>(std::lround(points[i].x)), 0, size.width - 1);
    const int v = std::clamp(static_cast<int>(std::lround(points[i].y)), 0, size.height - 1);
    px(v, u) += static_cast<float>(std::exp(lp(static_cast<Eigen::Index>(i))));
  }
  cv::GaussianBlur(px, px, cv::Size(), options.density_sigma);
  double hi = 0;
  cv::Point at;
  cv::minMaxLoc(px, nullptr, &hi, nullptr, &at);
  if (!(hi > 0)) {
    r.message = "p(x) is zero everywhere";
    return r;
  }
  px /= hi;
  r.px = px;
  double best = -std::numeric_limits<double>::infinity();
  for (double kappa : options.thresholds) {
    cv::Mat1b bin = px >= kappa;
    cv::Mat1i labels;
    cv::connectedComponents(bin, labels, 8, CV_32S);
    const int id = labels(at);
    cv::Mat1b region = labels == id;
    std::vector<Eigen::Index> rows;
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const int u = std::clamp(static_cast<int>(std::lround(points[i].x)), 0, size.width - 1);
      const int v = std::clamp(static_cast<int>(std::lround(points[i].y)), 0, size.height - 1);
      if (region(v, u) != 0) {
        rows.push_back(static_cast<Eigen::Index>(i));
        c += Eigen::Vector2d(points[i].x, points[i].y);
      }
    }
    if (static_cast<int>(rows.size()) < options.min_features) continue;
    Eigen::MatrixXd xin(static_cast<Eigen::Index>(rows.size()), x.cols());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      xin.row(static_cast<Eigen::Index>(i)) = x.row(rows[i]);
    }
    const Eigen::VectorXd pw =
        frame_word_distribution(model.words(), xin, options.sigma2).array().log().matrix();
    const double ld = model.dirichlet().log_density_of_log(pw);
    if (std::isfinite(ld) && ld > best) {
      best = ld;
      r.found = true;
      r.mask = region;
      r.kappa = kappa;
      r.log_density = ld;
      r.features = static_cast<int>(rows.size());
      r.centre = c / static_cast<double>(rows.size());
    }
  }
  r.message = r.found ? "recognised" : "no threshold's region has enough features";
  return r;
}

}  // namespace proprio::loop
