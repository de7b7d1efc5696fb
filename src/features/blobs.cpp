#include "proprio/features/blobs.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"

namespace proprio::features {

void BlobOptions::validate() const {
  require(sigma > 0 && std::isfinite(sigma), "blobs: sigma must be positive");
  require(threshold > 0 && std::isfinite(threshold), "blobs: threshold must be positive");
  require(min_features >= 1, "blobs: min_features must be >= 1");
}

cv::Mat1f feature_density(const std::vector<cv::KeyPoint>& keypoints, cv::Size image_size,
                          const BlobOptions& options) {
  options.validate();
  if (image_size.width <= 0 || image_size.height <= 0) {
    throw Error("blobs: empty image size " + std::to_string(image_size.width) + " x " +
                std::to_string(image_size.height));
  }
  // Padding by 3 sigma keeps the circular convolution of the DFT from wrapping density around
  // the borders; sizes are rounded up to ones the FFT is fast for.
  const int pad = static_cast<int>(std::ceil(3 * options.sigma));
  const int w = cv::getOptimalDFTSize(image_size.width + pad);
  const int h = cv::getOptimalDFTSize(image_size.height + pad);

  cv::Mat1f indicator(h, w, 0.0F);  // eq 6.2
  for (const auto& k : keypoints) {
    const int x = cvRound(k.pt.x);
    const int y = cvRound(k.pt.y);
    if (x >= 0 && y >= 0 && x < image_size.width && y < image_size.height) indicator(y, x) += 1;
  }
  // Peak-1 Gaussian centred at the origin (wrapped), so the product of spectra is h * N.
  cv::Mat1f kernel(h, w, 0.0F);
  const double s2 = 2 * options.sigma * options.sigma;
  for (int dy = -pad; dy <= pad; ++dy) {
    for (int dx = -pad; dx <= pad; ++dx) {
      kernel((dy + h) % h, (dx + w) % w) = static_cast<float>(std::exp(-(dx * dx + dy * dy) / s2));
    }
  }
  cv::Mat H;
  cv::Mat N;
  cv::dft(indicator, H, cv::DFT_COMPLEX_OUTPUT);
  cv::dft(kernel, N, cv::DFT_COMPLEX_OUTPUT);
  cv::Mat product;
  cv::mulSpectrums(H, N, product, 0);
  cv::Mat1f density;
  cv::dft(product, density, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT);  // eq 6.3
  return density(cv::Rect(0, 0, image_size.width, image_size.height)).clone();
}

std::vector<Blob> find_blobs(const std::vector<cv::KeyPoint>& keypoints, cv::Size image_size,
                             const BlobOptions& options) {
  const cv::Mat1f density = feature_density(keypoints, image_size, options);
  const cv::Mat1b above = density >= static_cast<float>(options.threshold);
  cv::Mat1i labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int n = cv::connectedComponentsWithStats(above, labels, stats, centroids, 8, CV_32S);
  std::vector<Blob> blobs(static_cast<std::size_t>(std::max(n - 1, 0)));
  for (int i = 0; i < static_cast<int>(keypoints.size()); ++i) {
    const int x = cvRound(keypoints[static_cast<std::size_t>(i)].pt.x);
    const int y = cvRound(keypoints[static_cast<std::size_t>(i)].pt.y);
    if (x < 0 || y < 0 || x >= image_size.width || y >= image_size.height) continue;
    const int l = labels(y, x);
    if (l > 0) blobs[static_cast<std::size_t>(l - 1)].features.push_back(i);
  }
  for (int l = 1; l < n; ++l) {
    auto& b = blobs[static_cast<std::size_t>(l - 1)];
    b.box = cv::Rect(stats.at<int>(l, cv::CC_STAT_LEFT), stats.at<int>(l, cv::CC_STAT_TOP),
                     stats.at<int>(l, cv::CC_STAT_WIDTH), stats.at<int>(l, cv::CC_STAT_HEIGHT));
    b.mask = labels(b.box) == l;
  }
  std::erase_if(blobs, [&](const Blob& b) {
    return static_cast<int>(b.features.size()) < options.min_features;
  });
  std::stable_sort(blobs.begin(), blobs.end(), [](const Blob& a, const Blob& b) {
    return a.features.size() > b.features.size();
  });
  return blobs;
}

}  // namespace proprio::features
