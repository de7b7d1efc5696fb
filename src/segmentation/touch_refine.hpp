#pragma once
// Private to the segmentation module: the touch frame's GrabCut refinement of M-L's mask
// (MlOptions::touch_fm_refine), apart so that its tests reach it without a whole recording.

#include <opencv2/core.hpp>

namespace proprio::segmentation {

/// GrabCut (OpenCV) on the touch frame `colour` (BGR, the map's size): `mask` (8-bit, 255 in
/// M-L's mask of `map`) eroded by `band` px is held as object, the scene beyond the mask dilated
/// by `band` px as background; the band's pixels follow GrabCut's labels in `map` (object: the
/// map's peak; background: 0). The pixels of `arm` (8-bit, the baseline's arm model; may be
/// empty) are left alone, except that with `settle_arm` the mask's pixels in it are settled too
/// (as probably object: colour decides). GrabCut runs on a crop round the band (16 px of scene
/// beyond it), so that its background mixture sees the scene next to the object. Leaves `map`
/// unchanged when the mask is empty, nothing is certainly object (the band erodes it all), or
/// either side has fewer than 5 samples (GrabCut fits 5-component mixtures and would throw: a
/// mask over the whole crop). Deterministic: OpenCV's thread-local generator is seeded for the
/// call and put back.
void refine_touch_outline(cv::Mat1f& map, const cv::Mat1b& mask, const cv::Mat3b& colour,
                          const cv::Mat1b& arm, int band, bool settle_arm);

}  // namespace proprio::segmentation
