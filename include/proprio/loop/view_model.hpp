#pragma once
// A visual vocabulary and an LDA model built from a set of training views' own descriptors, as
// `proprio experiment clutter` (Experiment 8.2) builds its own from the push views it learns from
// (and as `proprio learn` does without a given --vocabulary / --model): k-means over (a seeded
// sample of) the views' descriptors, then batch LDA over the views' documents. Shared by the
// clutter experiment, self-supervision's own-model rungs (SelfSupervisionOptions::
// own_model_rungs) and learn, so that they build them the same way.

#include <cstdint>
#include <span>

#include <opencv2/core.hpp>

#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::loop {

/// The vocabulary's k-means runs over at most this many of the views' descriptors (seeded; the
/// clutter experiment's and the own-model rungs' sample: learn's k-means sees every descriptor).
inline constexpr int kViewVocabularySample = 50000;
/// Batch LDA's EM iterations over the views (learn's and the clutter experiment's).
inline constexpr int kViewLdaIterations = 60;

/// A vocabulary of min(words, descriptors) words: k-means (seed `seed`, `threads` threads, 0 =
/// all cores: the words do not depend on it) over the stacked descriptors of `views` (CV_32F
/// rows, all of one width; empty views allowed), over a sample of `sample` of them drawn by
/// `seed` when there are more (0: every descriptor). Throws Error when the views hold no
/// descriptor, words < 1, sample < 0 or threads < 0.
features::Vocabulary views_vocabulary(std::span<const cv::Mat> views, int words, std::uint64_t seed,
                                      int sample = kViewVocabularySample, int threads = 1);

/// Batch LDA with `topics` topics (seed `seed`, kViewLdaIterations EM iterations) over `corpus`.
topics::LdaModel views_lda(const topics::Corpus& corpus, int topics, std::uint64_t seed);

}  // namespace proprio::loop
