"""proprio.recognition: objects as topics of visual words (thesis Ch 6, 7.3). Its pieces are
bound where they live: visual words in proprio.features (Vocabulary.quantize), topic models and
the Mixture of Topics classifier in proprio.topics. bag_of_words turns descriptors into a count
row for LatentDirichletAllocation."""

import numpy as np


def bag_of_words(vocabulary, descriptors) -> np.ndarray:
    """Counts of each word of `vocabulary` among the N x D float32 descriptors (one document)."""
    words = vocabulary.quantize(descriptors)
    return np.bincount(words, minlength=vocabulary.size).astype(np.int64)


__all__ = ["bag_of_words"]
