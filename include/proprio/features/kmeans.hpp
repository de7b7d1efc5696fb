#pragma once
// Building a vocabulary by k-means (thesis 6.1.2, 6.3.1): k-means++ seeding (Arthur &
// Vassilvitskii 2007), then Lloyd iterations until the relative change of the cost falls below
// the tolerance (the thesis stops "after the evolution fell below 0.1%").

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <utility>

#include "proprio/core/checkpoint.hpp"
#include "proprio/core/communicator.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/features/vocabulary.hpp"

namespace proprio::features {

struct KmeansOptions {
  int words = 400;           ///< K, the number of clusters (thesis: 400)
  int max_iterations = 100;  ///< Lloyd iterations at most (after seeding)
  /// Stop when (cost_before - cost_after) / cost_before falls below this (0.1%).
  double tolerance = 1e-3;
  std::uint64_t seed = 1;  ///< k-means++ seeding and the re-seeding of empty clusters
  int threads = 0;         ///< 0 = all cores
  /// Candidates per k-means++ step (greedy k-means++, as scikit-learn does; 0 = 2 + ln K, as
  /// scikit-learn's default; 1 is the plain algorithm of Arthur & Vassilvitskii).
  int seeding_trials = 0;
  /// k-means++ seeds from a uniform random sample of at most this many descriptors (0 = 32 *
  /// words); Lloyd's iterations then use all of them. Seeding over every descriptor would cost
  /// `words` passes over the data, more than all of Lloyd's iterations (see kmeans.cpp).
  int seeding_sample = 0;
  /// Throws Error on words < 1, max_iterations < 1, tolerance not in [0, 1), threads < 0,
  /// seeding_trials < 0, seeding_sample < 0.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.words, {"words", "Number of words K", core::at_least(1)});
    v(self.max_iterations, {"max_iterations", "Lloyd iterations at most", core::at_least(1)});
    v(self.tolerance, {"tolerance", "Relative decrease of the cost that stops Lloyd's iterations",
                       core::between(0, 1)});
    v(self.seed, {"seed", "Random seed (sampling and k-means++)"});
    v(self.threads,
      {"threads", "Threads (0 = all cores; the words do not depend on it)", core::at_least(0)});
    v(self.seeding_trials,
      {"seeding_trials", "Candidates per k-means++ step (0 = 2 + ln K)", core::at_least(0)});
    v(self.seeding_sample,
      {"seeding_sample", "Descriptors k-means++ seeds from, at most (0 = 32 x words)",
       core::at_least(0)});
  }
};

struct KmeansSummary {
  int iterations = 0;       ///< Lloyd iterations run
  double cost = 0;          ///< final sum of squared distances of every descriptor to its word
  double seconds = 0;       ///< wall time, seeding included
  std::string termination;  ///< "converged" (change below tolerance) or "max_iterations"
  int empty_clusters_reseeded = 0;
};

struct VocabularyResult {
  Vocabulary vocabulary;
  KmeansSummary summary;
};

/// k-means of the rows of `descriptors` (N x D CV_32F, finite) into options.words words.
/// Throws Error on an empty or non-finite descriptor set or when words > N. The same seed and
/// thread count give the same vocabulary.
VocabularyResult build_vocabulary(const cv::Mat& descriptors, const KmeansOptions& options = {});

/// The same, checkpointing and resuming (issue 16): with `checkpointing.checkpoint`, the centres
/// and the iteration count are written atomically every `checkpointing.every` Lloyd iterations
/// (core/checkpoint.hpp, kind "kmeans"); with `checkpointing.resume`, Lloyd's iterations continue
/// from those centres (no seeding). A run killed at any moment and resumed from its last
/// checkpoint gives the vocabulary of the uninterrupted run, bit for bit. Throws Error naming the
/// checkpoint when it was written over other descriptors or with other options (threads aside).
VocabularyResult build_vocabulary(const cv::Mat& descriptors, const KmeansOptions& options,
                                  const core::CheckpointOptions& checkpointing);

/// Data-parallel k-means (issue 23): the rows of the whole descriptor set that rank `rank` of
/// `ranks` holds, [first, last): whole chunks of the fixed chunks whose partial sums k-means adds
/// in order, so that the ranks' sums added in rank order are the one-process sums bit for bit.
std::pair<std::int64_t, std::int64_t> kmeans_rows_of_rank(std::int64_t total, int rank, int ranks);

/// One rank's share of a data-parallel k-means: rows [first, first + rows.rows) of a set of
/// `total` rows, as kmeans_rows_of_rank gives them.
struct DescriptorBlock {
  cv::Mat rows;
  std::int64_t first = 0;
  std::int64_t total = 0;
};

/// build_vocabulary over the descriptors of every rank of `comm`, collective: each rank assigns
/// its rows with its threads; sums, counts and costs are folded in rank order (core::
/// fold_in_rank_order), so every rank returns the vocabulary and summary that build_vocabulary
/// gives on the whole set in one process, bit for bit (seconds aside). The k-means++ sample is
/// gathered from the ranks that hold it. Throws Error (the same on every rank) as
/// build_vocabulary does.
VocabularyResult build_vocabulary(const DescriptorBlock& mine, const KmeansOptions& options,
                                  core::Communicator& comm);

/// The k-means cost (sum of squared distances to the nearest word) of `descriptors`.
double kmeans_cost(const Vocabulary& vocabulary, const cv::Mat& descriptors, int threads = 0);

}  // namespace proprio::features
