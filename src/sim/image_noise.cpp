#include "image_noise.hpp"
#include "proprio/core/random.hpp"

namespace proprio::sim {

namespace {

// The noise's stream: the seed xor "NOISE".
constexpr std::uint64_t kNoiseStream = 0x4e4f495345ULL;

}  // namespace

ImageNoise::ImageNoise(double sigma, std::uint64_t seed)
    : sigma_(sigma), rng_(core::stream_seed(seed, kNoiseStream)) {}

void ImageNoise::apply(cv::Mat& image) {
  if (sigma_ <= 0) return;
  cv::Mat n(image.size(), CV_16SC3);
  rng_.fill(n, cv::RNG::NORMAL, 0.0, sigma_);
  cv::Mat noisy;
  cv::add(image, n, noisy, cv::noArray(), CV_8UC3);
  image = noisy;
}

}  // namespace proprio::sim
