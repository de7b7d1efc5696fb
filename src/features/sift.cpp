#include "proprio/features/sift.hpp"

#include <array>
#include <cmath>
#include <numeric>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "proprio/core/error.hpp"

namespace proprio::features {

namespace {

cv::Mat grey_of(const cv::Mat& image, const char* what) {
  if (image.empty()) throw Error(std::string(what) + ": empty image");
  if (image.depth() != CV_8U) {
    throw Error(std::string(what) + ": the image must have 8-bit channels");
  }
  switch (image.channels()) {
    case 1:
      return image;
    case 3: {
      cv::Mat g;
      cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
      return g;
    }
    case 4: {
      cv::Mat g;
      cv::cvtColor(image, g, cv::COLOR_BGRA2GRAY);
      return g;
    }
    default:
      throw Error(std::string(what) + ": the image must have 1, 3 or 4 channels, not " +
                  std::to_string(image.channels()));
  }
}

Features empty_features() {
  Features f;
  f.descriptors.create(0, kDescriptorLength, CV_32F);
  return f;
}

}  // namespace

void SiftOptions::validate() const {
  require(max_features >= 0, "SIFT: max_features must be >= 0");
  require(octave_layers >= 1, "SIFT: octave_layers must be >= 1");
  require(contrast_threshold > 0, "SIFT: contrast_threshold must be positive");
  require(edge_threshold > 0, "SIFT: edge_threshold must be positive");
  require(sigma > 0, "SIFT: sigma must be positive");
}

Features detect_sift(const cv::Mat& image, const SiftOptions& options) {
  options.validate();
  const cv::Mat grey = grey_of(image, "SIFT");
  auto sift = cv::SIFT::create(options.max_features, options.octave_layers,
                               options.contrast_threshold, options.edge_threshold, options.sigma);
  Features f;
  sift->detectAndCompute(grey, cv::noArray(), f.keypoints, f.descriptors);
  if (f.keypoints.empty()) return empty_features();
  return f;
}

void DenseSiftOptions::validate() const {
  require(step >= 1, "dense SIFT: step must be >= 1 px");
  require(size > 0, "dense SIFT: size must be positive");
  require(margin >= -1, "dense SIFT: margin must be >= 0 (or -1 for size / 2)");
}

std::vector<cv::KeyPoint> dense_grid(cv::Size image_size, const DenseSiftOptions& options) {
  options.validate();
  const int margin =
      options.margin >= 0 ? options.margin : static_cast<int>(std::ceil(options.size / 2.0F));
  std::vector<cv::KeyPoint> grid;
  if (image_size.width <= 2 * margin || image_size.height <= 2 * margin) return grid;
  const int nx = (image_size.width - 1 - 2 * margin) / options.step + 1;
  const int ny = (image_size.height - 1 - 2 * margin) / options.step + 1;
  grid.reserve(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      grid.emplace_back(static_cast<float>(margin + i * options.step),
                        static_cast<float>(margin + j * options.step), options.size / 6.0F, 0.0F);
    }
  }
  return grid;
}

Features dense_sift(const cv::Mat& image, const DenseSiftOptions& options) {
  options.validate();
  const cv::Mat grey = grey_of(image, "dense SIFT");
  Features f;
  f.keypoints = dense_grid(grey.size(), options);
  if (f.keypoints.empty()) return empty_features();
  // Upright: cv::SIFT keeps a given keypoint's angle when it only computes descriptors; the
  // octave field 0 tells it the keypoint is at the first octave of its own scale space.
  auto sift = cv::SIFT::create();
  sift->compute(grey, f.keypoints, f.descriptors);
  if (f.keypoints.empty()) return empty_features();
  return f;
}

cv::Mat rotate_sift_descriptors(const cv::Mat& descriptors, int quarter_turns) {
  if (descriptors.empty()) return cv::Mat(0, 128, CV_32F);
  if (descriptors.cols != 128 || descriptors.type() != CV_32F) {
    throw Error("rotate_sift_descriptors: descriptors must be N x 128 CV_32F, got " +
                std::to_string(descriptors.rows) + " x " + std::to_string(descriptors.cols));
  }
  const int turns = ((quarter_turns % 4) + 4) % 4;
  // One quarter turn counter-clockwise: cell (r, c) -> (3 - c, r), bin b -> b + 2 (mod 8).
  std::array<int, 128> from{};  // out[k] = in[from[k]]
  std::iota(from.begin(), from.end(), 0);
  for (int t = 0; t < turns; ++t) {
    std::array<int, 128> next{};
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        for (int b = 0; b < 8; ++b) {
          const int to = ((((3 - c) * 4) + r) * 8) + ((b + 2) % 8);
          const int at = (((r * 4) + c) * 8) + b;
          next[static_cast<std::size_t>(to)] = from[static_cast<std::size_t>(at)];
        }
      }
    }
    from = next;
  }
  cv::Mat out(descriptors.rows, 128, CV_32F);
  for (int i = 0; i < descriptors.rows; ++i) {
    const auto* in = descriptors.ptr<float>(i);
    auto* o = out.ptr<float>(i);
    for (std::size_t k = 0; k < 128; ++k) o[k] = in[from[k]];
  }
  return out;
}

cv::Mat with_right_angle_turns(const cv::Mat& descriptors) {
  if (descriptors.empty()) return cv::Mat(0, 128, CV_32F);
  cv::Mat out;
  cv::vconcat(std::vector<cv::Mat>{descriptors.clone(), rotate_sift_descriptors(descriptors, 1),
                                   rotate_sift_descriptors(descriptors, 2),
                                   rotate_sift_descriptors(descriptors, 3)},
              out);
  return out;
}

}  // namespace proprio::features
