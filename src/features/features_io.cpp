#include <cassert>
#include <cmath>
#include <opencv2/core.hpp>

#include "proprio/core/binary_file.hpp"
#include "proprio/core/error.hpp"
#include "proprio/features/features.hpp"

namespace proprio::features {
namespace fs = std::filesystem;
using core::put_binary;

namespace {
constexpr core::BinaryFormat kFormat{"PRFEATS1", kFeaturesFormatVersion, "features"};
}  // namespace

void check_descriptors(const cv::Mat& descriptors, const std::string& what) {
  if (descriptors.empty()) throw Error(what + ": no descriptors");
  if (descriptors.type() != CV_32F || descriptors.channels() != 1 || descriptors.dims != 2) {
    throw Error(what + ": descriptors must be a one-channel float32 matrix");
  }
  if (descriptors.cols != kDescriptorLength) {
    throw Error(what + ": descriptors have " + std::to_string(descriptors.cols) +
                " columns, expected " + std::to_string(kDescriptorLength));
  }
  if (!cv::checkRange(descriptors, true)) {
    for (int r = 0; r < descriptors.rows; ++r) {
      const float* p = descriptors.ptr<float>(r);
      for (int c = 0; c < descriptors.cols; ++c) {
        if (!std::isfinite(p[c])) {
          throw Error(what + ": descriptor " + std::to_string(r) + " has a non-finite value (" +
                      std::to_string(p[c]) + ") in column " + std::to_string(c));
        }
      }
    }
  }
}

void write_features(const fs::path& path, const Features& features) {
  const auto n = static_cast<std::uint64_t>(features.keypoints.size());
  const bool have = n > 0;
  if (have) {
    assert(features.descriptors.rows == static_cast<int>(n));
    check_descriptors(features.descriptors, path.string());
  }
  std::string payload;
  payload.reserve(16 + n * (7 * 4 + kDescriptorLength * 4));
  put_binary<std::uint64_t>(payload, n);
  put_binary<std::uint32_t>(payload, static_cast<std::uint32_t>(kDescriptorLength));
  for (const auto& k : features.keypoints) {
    put_binary(payload, k.pt.x);
    put_binary(payload, k.pt.y);
    put_binary(payload, k.size);
    put_binary(payload, k.angle);
    put_binary(payload, k.response);
    put_binary<std::int32_t>(payload, k.octave);
    put_binary<std::int32_t>(payload, k.class_id);
  }
  if (have) {
    const cv::Mat d =
        features.descriptors.isContinuous() ? features.descriptors : features.descriptors.clone();
    payload.append(reinterpret_cast<const char*>(d.data), n * kDescriptorLength * sizeof(float));
  }
  core::write_binary_file(path, kFormat, payload);
}

Features read_features(const fs::path& path) {
  const std::string payload = core::read_binary_file(path, kFormat);
  core::BinaryReader r(payload, path, kFormat.kind);
  const auto n = r.get<std::uint64_t>("the count");
  const auto dim = r.get<std::uint32_t>("the descriptor length");
  if (dim != kDescriptorLength || n > (1ULL << 31) ||
      n * (7 * 4 + static_cast<std::uint64_t>(dim) * 4) != r.left()) {
    throw Error::in_file(path, "corrupt features file: " + std::to_string(n) +
                                   " features of length " + std::to_string(dim) +
                                   " do not fill its " + std::to_string(r.left()) + " bytes");
  }
  Features f;
  f.keypoints.resize(n);
  for (auto& k : f.keypoints) {
    k.pt.x = r.get<float>("x");
    k.pt.y = r.get<float>("y");
    k.size = r.get<float>("size");
    k.angle = r.get<float>("angle");
    k.response = r.get<float>("response");
    k.octave = r.get<std::int32_t>("octave");
    k.class_id = r.get<std::int32_t>("class id");
    if (!std::isfinite(k.pt.x) || !std::isfinite(k.pt.y) || !std::isfinite(k.size)) {
      throw Error::in_file(path, "corrupt features file: a keypoint is not finite");
    }
  }
  f.descriptors.create(static_cast<int>(n), kDescriptorLength, CV_32F);
  if (n > 0) {
    const auto data = r.take(n * kDescriptorLength * sizeof(float), "the descriptors");
    std::memcpy(f.descriptors.data, data.data(), data.size());
    try {
      check_descriptors(f.descriptors, path.string());
    } catch (const Error& e) {
      throw Error(std::string(e.what()));
    }
  }
  return f;
}

}  // namespace proprio::features
