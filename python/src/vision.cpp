// proprio._proprio.segmentation: Motion-Likelihood segmentation of an episode (thesis Ch 4), the
// map and mask as arrays.
#include "common.hpp"
#include "options.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::python {

namespace {

py::dict ml_result(const segmentation::MlResult& r) {
  py::dict d;
  d["map"] = array_from_image(r.map, false);
  d["mask"] = array_from_image(r.mask, false);
  d["scored_frame"] = r.scored_frame;
  d["first_touch_frame"] = r.first_touch_frame ? py::cast(*r.first_touch_frame) : py::none();
  py::list maps;
  for (const auto& f : r.frame_maps) maps.append(array_from_image(f, false));
  d["frame_maps"] = maps;
  d["message"] = r.summary.message;
  d["frames"] = r.summary.frames;
  d["touched"] = r.summary.touched;
  d["mean_ms_total"] = r.summary.mean_ms_total;
  return d;
}

}  // namespace

void bind_vision(py::module_& m) {
  bind_options<segmentation::MlOptions>(
      m, "MlOptions",
      "Motion-Likelihood segmentation (thesis Ch 4): the options a tuning run may set by name.");
  bind_options<segmentation::SparseOptions>(m, "SparseOptions",
                                            "The sparse M-L variant (Algorithm 3, 4.5).");
  m.def(
      "segment_ml",
      [](const episode::Episode& episode, const segmentation::MlOptions& options) {
        options.validate();
        segmentation::MlResult r;
        {
          py::gil_scoped_release release;
          r = segmentation::segment_ml(episode, options);
        }
        return ml_result(r);
      },
      py::arg("episode"), py::arg("options") = segmentation::MlOptions{},
      "Segments the pushed object of an episode. Returns a dict: map (H x W float32 in [0, 1], "
      "at the scored frame), mask (H x W uint8, 255 = object), scored_frame (-1: never "
      "touched), first_touch_frame, message. The arrays are copies. GIL released.");
  m.def(
      "segment_ml_sparse",
      [](const episode::Episode& episode, const segmentation::SparseOptions& options) {
        options.validate();
        segmentation::MlResult r;
        {
          py::gil_scoped_release release;
          r = segmentation::segment_ml_sparse(episode, options);
        }
        return ml_result(r);
      },
      py::arg("episode"), py::arg("options") = segmentation::SparseOptions{},
      "The sparse variant; the same dict as segment_ml.");
}

}  // namespace proprio::python
