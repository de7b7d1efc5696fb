#pragma once
// Disturbance (thesis 5.1, RecordOptions::noise): Gaussian noise added to every image.

#include <cstdint>
#include <opencv2/core.hpp>

namespace proprio::sim {

class ImageNoise {
 public:
  /// Standard deviation `sigma`, grey levels (none when <= 0); draws from a stream of `seed` of
  /// its own, so that switching it on leaves the rest alone.
  ImageNoise(double sigma, std::uint64_t seed);
  /// Adds fresh noise to an 8-bit 3-channel image, saturating.
  void apply(cv::Mat& image);

 private:
  double sigma_;
  cv::RNG rng_;
};

}  // namespace proprio::sim
