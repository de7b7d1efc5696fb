#include "touch_refine.hpp"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "proprio/features/mask_morphology.hpp"

namespace proprio::segmentation {

void refine_touch_outline(cv::Mat1f& map, const cv::Mat1b& mask, const cv::Mat3b& colour,
                          const cv::Mat1b& arm_in, int band, bool settle_arm) {
  assert(mask.size() == map.size() && colour.size() == map.size());
  assert((arm_in.empty() || arm_in.size() == map.size()) && band >= 0);
  if (cv::countNonZero(mask) == 0) return;
  const cv::Mat1b arm = arm_in.empty() ? cv::Mat1b(map.size(), uchar{0}) : arm_in;
  cv::Mat1b inner, outer, context;
  cv::erode(mask, inner, features::disc(band));
  cv::dilate(mask, outer, features::disc(band));
  constexpr int kContext = 16;  // px of scene round the band for the background's colours
  cv::dilate(outer, context, features::disc(kContext));
  const cv::Rect roi = cv::boundingRect(context);
  if (roi.width < 2 || roi.height < 2) return;
  cv::Mat1b gc(roi.size(), static_cast<uchar>(cv::GC_BGD));
  for (int y = 0; y < roi.height; ++y) {
    const uchar* in = inner[y + roi.y] + roi.x;
    const uchar* out = outer[y + roi.y] + roi.x;
    const uchar* mk = mask[y + roi.y] + roi.x;
    const uchar* a = arm[y + roi.y] + roi.x;
    uchar* l = gc[y];
    for (int x = 0; x < roi.width; ++x) {
      if (settle_arm && mk[x] != 0 && a[x] != 0) {
        l[x] = cv::GC_PR_FGD;  // the arm's rim or the object: colour decides
      } else if (in[x] != 0) {
        l[x] = cv::GC_FGD;
      } else if (out[x] != 0) {
        l[x] = mk[x] != 0 ? cv::GC_PR_FGD : cv::GC_PR_BGD;
      }
    }
  }
  // GrabCut fits 5-component colour mixtures by k-means to each side and throws when a side
  // has fewer samples (a mask over the whole crop: the frame changed everywhere at the touch).
  constexpr int kLeastSamples = 5;
  const int object_samples =
      cv::countNonZero(gc == cv::GC_FGD) + cv::countNonZero(gc == cv::GC_PR_FGD);
  if (cv::countNonZero(gc == cv::GC_FGD) == 0 || object_samples < kLeastSamples ||
      static_cast<int>(gc.total()) - object_samples < kLeastSamples) {
    return;
  }
  // GrabCut seeds its k-means from OpenCV's thread-local generator: a fixed state keeps the
  // result the same on every run and thread; the caller's state is put back.
  constexpr std::uint64_t kGrabCutSeed = 0x5EEDU;
  cv::RNG& rng = cv::theRNG();
  const std::uint64_t saved = rng.state;
  rng.state = kGrabCutSeed;
  cv::Mat bgd, fgd;
  cv::grabCut(colour(roi), gc, cv::Rect(), bgd, fgd, 2, cv::GC_INIT_WITH_MASK);
  rng.state = saved;
  double peak = 0;
  cv::minMaxLoc(map, nullptr, &peak);
  for (int y = 0; y < roi.height; ++y) {
    const uchar* in = inner[y + roi.y] + roi.x;
    const uchar* out = outer[y + roi.y] + roi.x;
    const uchar* a = arm[y + roi.y] + roi.x;
    const uchar* l = gc[y];
    float* o = map[y + roi.y] + roi.x;
    const uchar* mk = mask[y + roi.y] + roi.x;
    for (int x = 0; x < roi.width; ++x) {
      const bool settle = settle_arm && a[x] != 0 && mk[x] != 0;
      if (!settle && (in[x] != 0 || out[x] == 0 || a[x] != 0)) continue;
      const bool object = l[x] == cv::GC_FGD || l[x] == cv::GC_PR_FGD;
      o[x] = object ? std::max(o[x], static_cast<float>(peak)) : 0.0F;
    }
  }
}

}  // namespace proprio::segmentation
