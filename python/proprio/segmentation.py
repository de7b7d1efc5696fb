"""proprio.segmentation: Motion-Likelihood segmentation of a pushed object (thesis Ch 4).

    result = segment_ml(Episode.read(dir), MlOptions(mask_fraction=0.75))
    result["map"]   H x W float32 probability in [0, 1] at the scored (first-touch) frame
    result["mask"]  H x W uint8, 255 on the object
    result["scored_frame"], result["message"]

The arrays are copies of the library's images. The call releases the GIL.
"""

from . import _proprio

_g = _proprio.segmentation
MlOptions = _g.MlOptions
SparseOptions = _g.SparseOptions
segment_ml = _g.segment_ml
segment_ml_sparse = _g.segment_ml_sparse

__all__ = ["MlOptions", "SparseOptions", "segment_ml", "segment_ml_sparse"]
