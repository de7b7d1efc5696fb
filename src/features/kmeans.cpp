// k-means for visual vocabularies.
//
// Why our own rather than cv::kmeans or FAISS: FAISS is not installed here (and would be one
// more dependency for one function); cv::kmeans computes each point-centre distance on its own
// (no matrix product), 1.1 s an iteration for the thesis setting (300,000 x 128 into 400) on
// two threads. Here every iteration is one pass of the fused distance/arg-min kernel of
// nearest.inc (a blocked matrix product, ||x||^2 - 2 x.c + ||c||^2, AVX2/AVX-512 when the
// processor has them), split over threads; the centre sums are then made in double in a fixed
// number of chunks, so the result does not depend on the thread count. See
// docs/results/features.md for the measurements.
//
// Seeding is greedy k-means++ (Arthur & Vassilvitskii 2007; several candidates a step, the best
// kept, as scikit-learn and OpenCV do) on a random sample of the descriptors: exact k-means++
// over all of them needs one pass over the data per word (400 passes over 150 MB), more time
// than every Lloyd iteration together, while the start it gives is only a start.

#include "proprio/features/kmeans.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <span>
#include <string_view>

#include "nearest.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/core/checkpoint.hpp"
#include "proprio/core/communicator.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/core/parallel.hpp"
#include "proprio/core/random.hpp"

namespace proprio::features {

namespace {

using Clock = std::chrono::steady_clock;

// Chunks of the data whose partial sums are added in a fixed order (determinism).
constexpr std::size_t kChunks = 32;
constexpr std::size_t kBlock = 1024;  // rows per kernel call

double exact_sqdist(const float* a, const float* b, int D) {
  double s = 0;
  for (int d = 0; d < D; ++d) {
    const double t = static_cast<double>(a[d]) - b[d];
    s += t * t;
  }
  return s;
}

void check_input(const cv::Mat& x, const char* what) {
  if (x.rows == 0 || x.cols == 0) throw Error(std::string(what) + ": no descriptors");
  if (x.type() != CV_32F || x.dims != 2) {
    throw Error(std::string(what) + ": descriptors must be a one-channel float32 matrix");
  }
  if (!cv::checkRange(x, true)) {
    throw Error(std::string(what) + ": descriptors hold non-finite values (NaN or inf)");
  }
}

// Greedy k-means++ over the rows of `s` (n x D); returns K x D centres.
cv::Mat seed_centres(const cv::Mat& s, int K, int trials, core::Rng& rng, int threads) {
  const int n = s.rows;
  const int D = s.cols;
  cv::Mat centres(K, D, CV_32F);
  std::vector<float> mind(static_cast<std::size_t>(n));
  std::vector<float> cand_d(static_cast<std::size_t>(trials) * n);
  std::vector<double> prefix(static_cast<std::size_t>(n));
  const auto chunk_of = [n](std::size_t c) {
    return std::pair<int, int>{static_cast<int>(c * n / kChunks),
                               static_cast<int>((c + 1) * n / kChunks)};
  };

  int first = static_cast<int>(rng.index(static_cast<std::uint64_t>(n)));
  s.row(first).copyTo(centres.row(0));
  core::parallel_for(kChunks, threads, [&](std::size_t c, int) {
    const auto [a, b] = chunk_of(c);
    detail::squared_distances(s.ptr<float>(a), static_cast<std::size_t>(b - a), D,
                              centres.ptr<float>(0), mind.data() + a);
  });

  std::vector<int> cand(static_cast<std::size_t>(trials));
  std::vector<double> partial(kChunks * static_cast<std::size_t>(trials));
  for (int k = 1; k < K; ++k) {
    double total = 0;
    for (int i = 0; i < n; ++i) {
      total += mind[static_cast<std::size_t>(i)];
      prefix[static_cast<std::size_t>(i)] = total;
    }
    for (int t = 0; t < trials; ++t) {
      if (total > 0) {
        const double r = rng.uniform() * total;
        const auto it = std::upper_bound(prefix.begin(), prefix.end(), r);
        cand[static_cast<std::size_t>(t)] =
            static_cast<int>(std::min<std::ptrdiff_t>(it - prefix.begin(), n - 1));
      } else {  // every point is a centre already: duplicates are all that is left
        cand[static_cast<std::size_t>(t)] =
            static_cast<int>(rng.index(static_cast<std::uint64_t>(n)));
      }
    }
    core::parallel_for(kChunks, threads, [&](std::size_t c, int) {
      const auto [a, b] = chunk_of(c);
      for (int t = 0; t < trials; ++t) {
        const float* cp = s.ptr<float>(cand[static_cast<std::size_t>(t)]);
        float* out = cand_d.data() + static_cast<std::size_t>(t) * n;
        detail::squared_distances(s.ptr<float>(a), static_cast<std::size_t>(b - a), D, cp, out + a);
        double pot = 0;
        for (int i = a; i < b; ++i) {
          out[i] = std::min(out[i], mind[static_cast<std::size_t>(i)]);
          pot += out[i];
        }
        partial[c * static_cast<std::size_t>(trials) + static_cast<std::size_t>(t)] = pot;
      }
    });
    int best_t = 0;
    double best_pot = 0;
    for (int t = 0; t < trials; ++t) {
      double pot = 0;
      for (std::size_t c = 0; c < kChunks; ++c)
        pot += partial[c * static_cast<std::size_t>(trials) + static_cast<std::size_t>(t)];
      if (t == 0 || pot < best_pot) {
        best_t = t;
        best_pot = pot;
      }
    }
    s.row(cand[static_cast<std::size_t>(best_t)]).copyTo(centres.row(k));
    std::copy_n(cand_d.begin() + static_cast<std::ptrdiff_t>(best_t) * n, n, mind.begin());
  }
  return centres;
}

struct Assignment {
  std::vector<int> labels;
  std::vector<float> sq;  // squared distance to the label's centre (kernel precision)
  double cost = 0;
};

// Nearest centre of every row; the cost summed per chunk in a fixed order.
void assign(const cv::Mat& x, const cv::Mat& centres, int threads, Assignment& out) {
  const auto n = static_cast<std::size_t>(x.rows);
  out.labels.resize(n);
  out.sq.resize(n);
  const auto packed = detail::pack_centres(centres.ptr<float>(), centres.rows, centres.cols);
  std::vector<double> partial(kChunks, 0.0);
  core::parallel_for(kChunks, threads, [&](std::size_t c, int) {
    const std::size_t a = c * n / kChunks;
    const std::size_t b = (c + 1) * n / kChunks;
    for (std::size_t i = a; i < b; i += kBlock) {
      const std::size_t m = std::min(kBlock, b - i);
      detail::nearest_centres(x.ptr<float>(static_cast<int>(i)), m, packed, out.labels.data() + i,
                              out.sq.data() + i, nullptr);
    }
    double sum = 0;
    for (std::size_t i = a; i < b; ++i) sum += out.sq[i];
    partial[c] = sum;
  });
  out.cost = std::accumulate(partial.begin(), partial.end(), 0.0);
}

// Adds to total/count, in chunk order, the per-chunk sums (in double, rows in order) of the rows of
// chunks [c0, c1) of a data set of n rows of which `x` holds rows [first, first + x.rows).
void accumulate_chunks(const cv::Mat& x, const Assignment& as, std::size_t first, std::size_t n,
                       std::size_t c0, std::size_t c1, int K, int threads,
                       std::vector<double>& total, std::vector<long>& count) {
  const int D = x.cols;
  const auto kd = static_cast<std::size_t>(K) * D;
  const std::size_t group =
      std::clamp<std::size_t>((std::size_t{64} << 20) / (kd * sizeof(double)), 1, kChunks);
  std::vector<std::vector<double>> sums(group);
  std::vector<std::vector<int>> counts(group);
  for (std::size_t g0 = c0; g0 < c1; g0 += group) {
    const std::size_t g1 = std::min(c1, g0 + group);
    core::parallel_for(g1 - g0, threads, [&](std::size_t j, int) {
      const std::size_t c = g0 + j;
      auto& s = sums[j];
      auto& cnt = counts[j];
      s.assign(kd, 0.0);
      cnt.assign(static_cast<std::size_t>(K), 0);
      const std::size_t a = c * n / kChunks - first;
      const std::size_t b = (c + 1) * n / kChunks - first;
      for (std::size_t i = a; i < b; ++i) {
        const int l = as.labels[i];
        const float* p = x.ptr<float>(static_cast<int>(i));
        double* dst = s.data() + static_cast<std::size_t>(l) * D;
        for (int d = 0; d < D; ++d) dst[d] += p[d];
        ++cnt[static_cast<std::size_t>(l)];
      }
    });
    for (std::size_t j = 0; j < g1 - g0; ++j) {
      for (std::size_t e = 0; e < kd; ++e) total[e] += sums[j][e];
      for (int k = 0; k < K; ++k) {
        count[static_cast<std::size_t>(k)] += counts[j][static_cast<std::size_t>(k)];
      }
    }
  }
}

// Centres = means of their points (sums in double per chunk, added in chunk order). Empty
// clusters take the points farthest from their centres. Returns how many were empty.
int update_centres(const cv::Mat& x, const Assignment& as, cv::Mat& centres, int threads) {
  const int K = centres.rows;
  const int D = centres.cols;
  const auto n = static_cast<std::size_t>(x.rows);
  const auto kd = static_cast<std::size_t>(K) * D;
  // One accumulator per chunk (not per thread), added in chunk order: the same result for any
  // thread count, and for any number of MPI ranks owning whole chunks (issue 23). At most ~64 MB
  // of accumulators at once for large K x D (10,000 words): the chunks then go in groups.
  std::vector<double> total(kd, 0.0);
  std::vector<long> count(static_cast<std::size_t>(K), 0);
  accumulate_chunks(x, as, 0, n, 0, kChunks, K, threads, total, count);
  int empty = 0;
  std::vector<std::size_t> far;
  for (int k = 0; k < K; ++k) {
    float* cp = centres.ptr<float>(k);
    const long m = count[static_cast<std::size_t>(k)];
    if (m > 0) {
      for (int d = 0; d < D; ++d)
        cp[d] =
            static_cast<float>(total[static_cast<std::size_t>(k) * D + d] / static_cast<double>(m));
      continue;
    }
    if (far.empty()) {
      far.resize(n);
      std::iota(far.begin(), far.end(), std::size_t{0});
      // Farthest first; ties by index so the order is reproducible.
      std::stable_sort(far.begin(), far.end(),
                       [&](std::size_t a, std::size_t b) { return as.sq[a] > as.sq[b]; });
    }
    const std::size_t i = far[static_cast<std::size_t>(empty) % n];
    x.row(static_cast<int>(i)).copyTo(centres.row(k));
    ++empty;
  }
  return empty;
}

}  // namespace

void KmeansOptions::validate() const {
  require(words >= 1, "k-means: words must be >= 1");
  require(max_iterations >= 1, "k-means: max_iterations must be >= 1");
  require(tolerance >= 0 && tolerance < 1, "k-means: tolerance must be in [0, 1)");
  require(threads >= 0, "k-means: threads must be >= 0 (0 = all cores)");
  require(seeding_trials >= 0, "k-means: seeding_trials must be >= 0");
  require(seeding_sample >= 0, "k-means: seeding_sample must be >= 0");
}

namespace {

constexpr const char* kKmeansCheckpointKind = "kmeans";

// The checkpoint's identity: the descriptors and every option the words depend on.
core::Checkpoint kmeans_identity(const cv::Mat& x, const KmeansOptions& o) {
  core::Checkpoint c;
  c.kind = kKmeansCheckpointKind;
  const std::int64_t head[2] = {x.rows, x.cols};
  std::uint64_t h = core::fnv1a(std::string_view(reinterpret_cast<const char*>(head), sizeof head),
                                core::fnv1a("kmeans"));
  c.input_checksum = core::fnv1a(
      std::string_view(reinterpret_cast<const char*>(x.ptr<float>()), x.total() * x.elemSize()), h);
  c.options = {{"words", std::to_string(o.words)},
               {"max_iterations", std::to_string(o.max_iterations)},
               {"tolerance", core::exact_text(o.tolerance)},
               {"seed", std::to_string(o.seed)},
               {"seeding_trials", std::to_string(o.seeding_trials)},
               {"seeding_sample", std::to_string(o.seeding_sample)}};
  return c;
}

std::string kmeans_state(const cv::Mat& centres, const KmeansSummary& s, bool converged) {
  std::string out;
  core::put_binary<std::int32_t>(out, s.iterations);
  core::put_binary<std::int32_t>(out, s.empty_clusters_reseeded);
  core::put_binary<std::int32_t>(out, converged ? 1 : 0);
  core::put_binary<double>(out, s.seconds);
  core::put_binary<std::int32_t>(out, centres.rows);
  core::put_binary<std::int32_t>(out, centres.cols);
  out.append(reinterpret_cast<const char*>(centres.ptr<float>()),
             centres.total() * centres.elemSize());
  return out;
}

// Reads kmeans_state's layout into `centres` (K x D, as this run has them); the sizes are checked
// against this run's and against the bytes left before anything is copied.
void parse_kmeans_state(std::string_view state, const std::filesystem::path& source,
                        const KmeansOptions& o, cv::Mat& centres, KmeansSummary& s) {
  core::BinaryReader in(state, source, "checkpoint");
  s.iterations = in.get<std::int32_t>("the iterations");
  s.empty_clusters_reseeded = in.get<std::int32_t>("the re-seeded clusters");
  const auto converged = in.get<std::int32_t>("whether it converged");
  if (converged != 0 && converged != 1) {
    throw Error::in_file(
        source, "corrupt checkpoint file: a converged flag of " + std::to_string(converged));
  }
  s.termination = converged != 0 ? "converged" : "";
  s.seconds = in.get<double>("the seconds");
  const auto K = in.get<std::int32_t>("the number of words");
  const auto D = in.get<std::int32_t>("the dimension");
  if (K != centres.rows || D != centres.cols || s.iterations < 0 ||
      s.iterations > o.max_iterations || s.empty_clusters_reseeded < 0 ||
      !std::isfinite(s.seconds)) {
    throw Error::in_file(source, "corrupt checkpoint file: its centres or progress do not fit");
  }
  const std::size_t bytes = centres.total() * centres.elemSize();
  const std::string_view data = in.take(bytes, "the centres");
  if (in.left() != 0)
    throw Error::in_file(source, "corrupt checkpoint file: bytes after the centres");
  std::memcpy(centres.ptr<float>(), data.data(), bytes);
  if (!cv::checkRange(centres, true)) {
    throw Error::in_file(source, "corrupt checkpoint file: centres that are not finite");
  }
}

VocabularyResult build_vocabulary_impl(const cv::Mat& descriptors, const KmeansOptions& options,
                                       const core::CheckpointOptions* checkpointing) {
  options.validate();
  if (checkpointing != nullptr) checkpointing->validate();
  check_input(descriptors, "k-means");
  const auto t0 = Clock::now();
  const cv::Mat x = descriptors.isContinuous() ? descriptors : descriptors.clone();
  const int N = x.rows;
  const int K = options.words;
  if (K > N) {
    throw Error("k-means: " + std::to_string(K) + " words from " + std::to_string(N) +
                " descriptors (need at least as many descriptors as words)");
  }
  core::Rng rng(options.seed);
  const int trials = options.seeding_trials > 0
                         ? options.seeding_trials
                         : 2 + static_cast<int>(std::log(static_cast<double>(K)));
  const long sample_max = options.seeding_sample > 0 ? options.seeding_sample : 32L * K;
  cv::Mat sample;
  if (sample_max >= N) {
    sample = x;
  } else {
    // A uniform sample without replacement (partial Fisher-Yates), kept in data order.
    std::vector<int> idx(static_cast<std::size_t>(N));
    std::iota(idx.begin(), idx.end(), 0);
    for (long i = 0; i < sample_max; ++i) {
      const auto j = static_cast<std::size_t>(i) + rng.index(static_cast<std::uint64_t>(N - i));
      std::swap(idx[static_cast<std::size_t>(i)], idx[j]);
    }
    idx.resize(static_cast<std::size_t>(std::max<long>(sample_max, K)));
    std::sort(idx.begin(), idx.end());
    sample.create(static_cast<int>(idx.size()), x.cols, CV_32F);
    for (std::size_t i = 0; i < idx.size(); ++i)
      x.row(idx[i]).copyTo(sample.row(static_cast<int>(i)));
  }
  const bool saving = checkpointing != nullptr && !checkpointing->checkpoint.empty();
  const bool resuming = checkpointing != nullptr && !checkpointing->resume.empty();
  core::Checkpoint identity;
  if (saving || resuming) identity = kmeans_identity(x, options);
  KmeansSummary summary;
  cv::Mat centres;
  double seconds_before = 0;
  if (resuming) {
    // The state after some Lloyd iterations replaces the seeding (which alone draws from rng).
    const core::Checkpoint found = core::load_checkpoint(checkpointing->resume);
    core::check_checkpoint_matches(found, identity, checkpointing->resume, "descriptor set");
    centres.create(K, x.cols, CV_32F);
    parse_kmeans_state(found.state, checkpointing->resume, options, centres, summary);
    seconds_before = summary.seconds;
  } else {
    centres = seed_centres(sample, K, trials, rng, options.threads);
  }

  Assignment as;
  assign(x, centres, options.threads, as);
  // A checkpoint written at the iteration that converged resumes to its end.
  const bool done = summary.termination == "converged";
  if (!done) summary.termination = "max_iterations";
  while (!done && summary.iterations < options.max_iterations) {
    const double before = as.cost;
    const int empty = update_centres(x, as, centres, options.threads);
    summary.empty_clusters_reseeded += empty;
    ++summary.iterations;
    assign(x, centres, options.threads, as);
    const bool converged =
        empty == 0 && (before <= 0 || (before - as.cost) / before <= options.tolerance);
    if (saving && summary.iterations % checkpointing->every == 0) {
      summary.seconds = seconds_before + std::chrono::duration<double>(Clock::now() - t0).count();
      core::Checkpoint c = identity;
      c.state = kmeans_state(centres, summary, converged);
      core::save_checkpoint(c, checkpointing->checkpoint);
    }
    if (converged) {
      summary.termination = "converged";
      break;
    }
  }
  // The reported cost in double from the final labels, which are the nearest centres.
  double cost = 0;
  for (int i = 0; i < N; ++i) {
    cost += exact_sqdist(x.ptr<float>(i),
                         centres.ptr<float>(as.labels[static_cast<std::size_t>(i)]), x.cols);
  }
  summary.cost = cost;
  summary.seconds = seconds_before + std::chrono::duration<double>(Clock::now() - t0).count();
  return {Vocabulary(centres), summary};
}

}  // namespace

VocabularyResult build_vocabulary(const cv::Mat& descriptors, const KmeansOptions& options) {
  return build_vocabulary_impl(descriptors, options, nullptr);
}

VocabularyResult build_vocabulary(const cv::Mat& descriptors, const KmeansOptions& options,
                                  const core::CheckpointOptions& checkpointing) {
  return build_vocabulary_impl(descriptors, options, &checkpointing);
}

std::pair<std::int64_t, std::int64_t> kmeans_rows_of_rank(std::int64_t total, int rank, int ranks) {
  const auto chunks = static_cast<std::int64_t>(kChunks);
  const std::int64_t c0 = rank * chunks / ranks;
  const std::int64_t c1 = (rank + 1) * chunks / ranks;
  return {c0 * total / chunks, c1 * total / chunks};
}

VocabularyResult build_vocabulary(const DescriptorBlock& mine, const KmeansOptions& options,
                                  core::Communicator& comm) {
  const int rank = comm.rank();
  const int ranks = comm.size();
  const auto N = static_cast<std::size_t>(mine.total);
  const auto first = static_cast<std::size_t>(mine.first);
  const int K = options.words;
  int D = mine.rows.cols;
  cv::Mat x;
  core::agree(comm, [&] {
    options.validate();
    const auto [lo, hi] = kmeans_rows_of_rank(mine.total, rank, ranks);
    ensure(lo == mine.first && hi - lo == mine.rows.rows, "k-means: a rank holds the wrong rows");
    if (mine.total == 0) throw Error("k-means: no descriptors");
    if (!mine.rows.empty()) check_input(mine.rows, "k-means");
    if (K > mine.total) {
      throw Error("k-means: " + std::to_string(K) + " words from " + std::to_string(mine.total) +
                  " descriptors (need at least as many descriptors as words)");
    }
  });
  // Every rank must run the same k-means (all options but the threads, which change no bit).
  KmeansOptions same = options;
  same.threads = 0;
  core::require_same_on_every_rank(comm, core::fields_to_json(same).dump(),
                                   "k-means: the " + std::to_string(ranks) +
                                       " MPI ranks were given different options (every option "
                                       "but the threads must be the same on every rank)");
  std::vector<std::int64_t> dims{D};
  comm.allreduce_max(dims);
  D = static_cast<int>(dims[0]);
  x = mine.rows.empty() ? cv::Mat(0, D, CV_32F)
                        : (mine.rows.isContinuous() ? mine.rows : mine.rows.clone());
  const auto t0 = Clock::now();
  const auto own = static_cast<std::size_t>(x.rows);
  const std::size_t c0 = static_cast<std::size_t>(rank) * kChunks / static_cast<std::size_t>(ranks);
  const std::size_t c1 =
      static_cast<std::size_t>(rank + 1) * kChunks / static_cast<std::size_t>(ranks);

  // Seeding, as one process: the same draws over all N rows, the sampled rows gathered.
  core::Rng rng(options.seed);
  const int trials = options.seeding_trials > 0
                         ? options.seeding_trials
                         : 2 + static_cast<int>(std::log(static_cast<double>(K)));
  const long sample_max = options.seeding_sample > 0 ? options.seeding_sample : 32L * K;
  std::vector<float> rows_out;
  if (sample_max >= static_cast<long>(N)) {
    rows_out.assign(x.ptr<float>(), x.ptr<float>() + own * static_cast<std::size_t>(D));
  } else {
    std::vector<int> idx(N);
    std::iota(idx.begin(), idx.end(), 0);
    for (long i = 0; i < sample_max; ++i) {
      const auto j = static_cast<std::size_t>(i) +
                     rng.index(static_cast<std::uint64_t>(static_cast<long>(N) - i));
      std::swap(idx[static_cast<std::size_t>(i)], idx[j]);
    }
    idx.resize(static_cast<std::size_t>(std::max<long>(sample_max, K)));
    std::sort(idx.begin(), idx.end());
    for (const int i : idx) {
      const auto g = static_cast<std::size_t>(i);
      if (g < first || g >= first + own) continue;
      const float* p = x.ptr<float>(static_cast<int>(g - first));
      rows_out.insert(rows_out.end(), p, p + D);
    }
  }
  std::vector<float> sampled = core::allgather_values<float>(comm, rows_out);
  const cv::Mat sample(static_cast<int>(sampled.size() / static_cast<std::size_t>(D)), D, CV_32F,
                       sampled.data());
  cv::Mat centres = seed_centres(sample, K, trials, rng, options.threads);

  // Assignment of this rank's rows; the cost folded over the chunks in order.
  Assignment as;
  auto assign_mine = [&] {
    as.labels.resize(own);
    as.sq.resize(own);
    const auto packed = detail::pack_centres(centres.ptr<float>(), centres.rows, centres.cols);
    std::vector<double> partial(kChunks, 0.0);
    core::parallel_for(c1 - c0, options.threads, [&](std::size_t j, int) {
      const std::size_t c = c0 + j;
      const std::size_t a = c * N / kChunks - first;
      const std::size_t b = (c + 1) * N / kChunks - first;
      for (std::size_t i = a; i < b; i += kBlock) {
        const std::size_t m = std::min(kBlock, b - i);
        detail::nearest_centres(x.ptr<float>(static_cast<int>(i)), m, packed, as.labels.data() + i,
                                as.sq.data() + i, nullptr);
      }
      double sum = 0;
      for (std::size_t i = a; i < b; ++i) sum += as.sq[i];
      partial[c] = sum;
    });
    std::vector<double> cost{0.0};
    core::fold_in_rank_order(comm, cost, [&](std::span<double> acc) {
      for (std::size_t c = c0; c < c1; ++c) acc[0] += partial[c];
    });
    as.cost = cost[0];
  };
  // Centres from the sums and counts folded over the chunks in order.
  auto update_mine = [&] {
    const auto kd = static_cast<std::size_t>(K) * static_cast<std::size_t>(D);
    std::vector<double> acc(kd + static_cast<std::size_t>(K), 0.0);
    core::fold_in_rank_order(comm, acc, [&](std::span<double> a) {
      std::vector<double> total(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(kd));
      std::vector<long> count(static_cast<std::size_t>(K));
      for (int k = 0; k < K; ++k)
        count[static_cast<std::size_t>(k)] = static_cast<long>(a[kd + static_cast<std::size_t>(k)]);
      accumulate_chunks(x, as, first, N, c0, c1, K, options.threads, total, count);
      std::copy(total.begin(), total.end(), a.begin());
      for (int k = 0; k < K; ++k)
        a[kd + static_cast<std::size_t>(k)] =
            static_cast<double>(count[static_cast<std::size_t>(k)]);
    });
    int empty = 0;
    std::vector<std::size_t> far;
    std::vector<float> sq_all;
    for (int k = 0; k < K; ++k) {
      float* cp = centres.ptr<float>(k);
      const auto m = static_cast<long>(acc[kd + static_cast<std::size_t>(k)]);
      if (m > 0) {
        for (int d = 0; d < D; ++d)
          cp[d] =
              static_cast<float>(acc[static_cast<std::size_t>(k) * D + d] / static_cast<double>(m));
        continue;
      }
      if (far.empty()) {
        sq_all = core::allgather_values<float>(comm, as.sq);
        far.resize(N);
        std::iota(far.begin(), far.end(), std::size_t{0});
        std::stable_sort(far.begin(), far.end(),
                         [&](std::size_t a, std::size_t b) { return sq_all[a] > sq_all[b]; });
      }
      const std::size_t i = far[static_cast<std::size_t>(empty) % N];
      int owner = 0;
      while (kmeans_rows_of_rank(mine.total, owner, ranks).second <= static_cast<std::int64_t>(i))
        ++owner;
      if (owner == rank) x.row(static_cast<int>(i - first)).copyTo(centres.row(k));
      comm.broadcast(std::as_writable_bytes(std::span(cp, static_cast<std::size_t>(D))), owner);
      ++empty;
    }
    return empty;
  };

  KmeansSummary summary;
  assign_mine();
  summary.termination = "max_iterations";
  while (summary.iterations < options.max_iterations) {
    const double before = as.cost;
    const int empty = update_mine();
    summary.empty_clusters_reseeded += empty;
    ++summary.iterations;
    assign_mine();
    if (empty == 0 && (before <= 0 || (before - as.cost) / before <= options.tolerance)) {
      summary.termination = "converged";
      break;
    }
  }
  std::vector<double> cost{0.0};
  core::fold_in_rank_order(comm, cost, [&](std::span<double> acc) {
    for (std::size_t i = 0; i < own; ++i) {
      acc[0] +=
          exact_sqdist(x.ptr<float>(static_cast<int>(i)), centres.ptr<float>(as.labels[i]), D);
    }
  });
  summary.cost = cost[0];
  summary.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return {Vocabulary(centres), summary};
}

double kmeans_cost(const Vocabulary& vocabulary, const cv::Mat& descriptors, int threads) {
  check_input(descriptors, "k-means cost");
  const cv::Mat x = descriptors.isContinuous() ? descriptors : descriptors.clone();
  const auto labels = vocabulary.quantize(x, threads);
  double cost = 0;
  for (int i = 0; i < x.rows; ++i) {
    cost +=
        exact_sqdist(x.ptr<float>(i),
                     vocabulary.words().ptr<float>(labels[static_cast<std::size_t>(i)]), x.cols);
  }
  return cost;
}

}  // namespace proprio::features
