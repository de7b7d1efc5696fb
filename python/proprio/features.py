"""proprio.features: local features and visual vocabularies (thesis 6.1).

    points, descriptors = extract_features(rgb_image, ExtractOptions(kind="dense"))
    vocabulary, summary = build_vocabulary(descriptors, KmeansOptions(words=400))
    words = vocabulary.quantize(descriptors)            # int32 word id per row
    vocabulary, summary = build_vocabulary_from_images("images/", out="vocab.bin")

Descriptors are N x 128 float32, C-contiguous (read in place by quantize/build_vocabulary: no
copy); a wrong dtype, shape or a non-contiguous array is a ValueError naming the argument.
Images are H x W x 3 uint8 RGB (copied to BGR for the library).
"""

from . import _proprio

_f = _proprio.features
ExtractOptions = _f.ExtractOptions
KmeansOptions = _f.KmeansOptions
Vocabulary = _f.Vocabulary
build_vocabulary = _f.build_vocabulary
build_vocabulary_from_images = _f.build_vocabulary_from_images
extract_features = _f.extract_features

__all__ = ["ExtractOptions", "KmeansOptions", "Vocabulary", "build_vocabulary",
           "build_vocabulary_from_images", "extract_features"]
