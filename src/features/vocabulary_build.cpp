#include "proprio/features/vocabulary_build.hpp"
#include "proprio/core/files.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <span>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/geometry/image_file.hpp"

namespace proprio::features {
namespace {

using Clock = std::chrono::steady_clock;

// Images are read as grey by the decoder (extract_file_features(..., grey = true)), as `vocab
// build` always has: the vocabulary's bytes depend on it.

// A uniform sample of `count` rows without replacement (partial Fisher-Yates), in row order.
void append_sample(const cv::Mat& descriptors, int count, core::Rng& rng, cv::Mat& all) {
  const int n = descriptors.rows;
  if (count == 0 || n <= count) {
    all.push_back(descriptors);
    return;
  }
  std::vector<int> idx(static_cast<std::size_t>(n));
  std::iota(idx.begin(), idx.end(), 0);
  for (int i = 0; i < count; ++i) {
    std::swap(idx[static_cast<std::size_t>(i)],
              idx[static_cast<std::size_t>(i) + rng.index(static_cast<std::uint64_t>(n - i))]);
  }
  idx.resize(static_cast<std::size_t>(count));
  std::sort(idx.begin(), idx.end());
  for (const int i : idx) all.push_back(descriptors.row(i));
}

void fill_document(const VocabularyBuildOptions& options, const core::Provenance& provenance,
                   VocabularyBuildResult& r) {
  r.options = options;
  r.document = core::result_document("proprio.vocab.build", 1, provenance);
  core::fields_into_json(r, r.document);
}

}  // namespace

void VocabularyBuildOptions::validate() const {
  if (images.empty()) throw Error("vocab build: the image set is required");
  core::require_output_not_input(out, {images}, "--out");
  checkpointing.validate();
  if (!checkpointing.checkpoint.empty()) {
    core::require_output_not_input(checkpointing.checkpoint, {images, out}, "--checkpoint");
  }
  if (!checkpointing.resume.empty()) {
    core::require_output_not_input(out, {checkpointing.resume}, "--out");
  }
  core::check_field_bounds(*this, "vocab build");
  features.validate();
  kmeans.validate();
}

std::string VocabularyBuildResult::brief() const {
  char line[320];
  std::snprintf(line, sizeof line,
                "%d words from %d descriptors of %zu images (%d without features): extraction "
                "%.2f s, k-means %.2f s, %d iterations (%s), cost %.6g",
                vocabulary.size(), descriptors, images, images_without_features, extract_seconds,
                kmeans.seconds, kmeans.iterations, kmeans.termination.c_str(), kmeans.cost);
  return line;
}

VocabularyBuildResult run_vocabulary_build(const VocabularyBuildOptions& options,
                                           const core::Provenance& provenance) {
  options.validate();
  const ImageSet set = read_image_set(options.images);
  core::Rng rng(options.kmeans.seed);
  cv::Mat all;
  int without = 0;
  const auto t0 = Clock::now();
  {
    core::ProgressBar bar(set.images.size(), "descriptors", options.progress);
    for (const auto& path : set.images) {
      const Features f = extract_file_features(path, options.features, /*grey=*/true);
      bar.tick();
      if (f.empty()) {
        ++without;
        continue;
      }
      append_sample(f.descriptors, options.per_image, rng, all);
    }
  }
  const double extract_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (all.empty()) throw Error::in_file(options.images, "no features in any of its images");
  if (all.rows < options.kmeans.words) {
    throw Error::in_file(options.images, std::to_string(all.rows) + " descriptors from " +
                                             std::to_string(set.images.size()) +
                                             " images, fewer than " +
                                             std::to_string(options.kmeans.words) + " words");
  }
  VocabularyResult v = build_vocabulary(all, options.kmeans, options.checkpointing);
  VocabularyBuildResult r{std::move(v.vocabulary),
                          v.summary,
                          set.classes.size(),
                          set.images.size(),
                          without,
                          all.rows,
                          extract_seconds,
                          {},
                          {},
                          core::Json(),
                          {}};
  if (!options.out.empty()) write_vocabulary(options.out, r.vocabulary, provenance);
  fill_document(options, provenance, r);
  r.message = core::first_line(r.brief());
  return r;
}

VocabularyBuildResult run_vocabulary_build(const VocabularyBuildOptions& options,
                                           const core::Provenance& provenance,
                                           core::Communicator& comm) {
  if (comm.size() == 1) {
    std::optional<VocabularyBuildResult> r;
    core::agree(comm, [&] { r.emplace(run_vocabulary_build(options, provenance)); });
    return std::move(*r);
  }
  const int rank = comm.rank();
  const int ranks = comm.size();
  ImageSet set;
  core::agree(comm, [&] {
    options.validate();
    if (!options.checkpointing.checkpoint.empty() || !options.checkpointing.resume.empty()) {
      throw Error("vocab build: --checkpoint and --resume run in one process, not under mpirun");
    }
    set = read_image_set(options.images);
  });
  // Every rank must extract and sample alike (the k-means checks its own options again).
  KmeansOptions kmeans = options.kmeans;
  kmeans.threads = 0;
  core::require_same_on_every_rank(
      comm,
      core::fields_to_json(options).dump() + core::fields_to_json(options.features).dump() +
          core::fields_to_json(kmeans).dump(),
      "vocab build: the " + std::to_string(ranks) +
          " MPI ranks were given different options (every option but the threads must be the "
          "same on every rank)");
  // 1. This rank's images' features.
  const std::size_t I = set.images.size();
  std::vector<cv::Mat> own(I);
  std::vector<std::int64_t> n(I, 0);
  const auto t0 = Clock::now();
  core::agree(comm, [&] {
    core::ProgressBar bar(
        (I + static_cast<std::size_t>(ranks) - 1) / static_cast<std::size_t>(ranks), "descriptors",
        options.progress && rank == 0);
    for (std::size_t i = static_cast<std::size_t>(rank); i < I;
         i += static_cast<std::size_t>(ranks)) {
      const Features f = extract_file_features(set.images[i], options.features, /*grey=*/true);
      bar.tick();
      if (f.empty()) continue;
      own[i] = f.descriptors;
      n[i] = f.descriptors.rows;
    }
  });
  comm.allreduce_sum(n);
  // 2. Every image's sample, as one process draws it, image after image.
  core::Rng rng(options.kmeans.seed);
  int without = 0;
  const int count = options.per_image;
  std::vector<std::int64_t> offset(I + 1, 0);
  std::vector<std::vector<int>> picked(I);  // sampled rows of this rank's images
  for (std::size_t i = 0; i < I; ++i) {
    const auto rows = static_cast<int>(n[i]);
    offset[i + 1] = offset[i];
    if (rows == 0) {
      ++without;
      continue;
    }
    const bool mine = i % static_cast<std::size_t>(ranks) == static_cast<std::size_t>(rank);
    if (count == 0 || rows <= count) {
      offset[i + 1] += rows;
      if (mine) {
        picked[i].resize(static_cast<std::size_t>(rows));
        std::iota(picked[i].begin(), picked[i].end(), 0);
      }
      continue;
    }
    std::vector<int> idx(static_cast<std::size_t>(rows));
    std::iota(idx.begin(), idx.end(), 0);
    for (int j = 0; j < count; ++j) {
      std::swap(idx[static_cast<std::size_t>(j)],
                idx[static_cast<std::size_t>(j) + rng.index(static_cast<std::uint64_t>(rows - j))]);
    }
    idx.resize(static_cast<std::size_t>(count));
    std::sort(idx.begin(), idx.end());
    offset[i + 1] += count;
    if (mine) picked[i] = std::move(idx);
  }
  const double extract_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const std::int64_t N = offset[I];
  if (N == 0)
    throw core::CollectiveError(
        Error::in_file(options.images, "no features in any of its images").what());
  if (N < options.kmeans.words) {
    throw core::CollectiveError(
        Error::in_file(options.images, std::to_string(N) + " descriptors from " +
                                           std::to_string(I) + " images, fewer than " +
                                           std::to_string(options.kmeans.words) + " words")
            .what());
  }
  // 3. The sampled rows to the ranks that hold their k-means chunks: rank q sends rank r, in image
  // order, its rows that fall in r's block; pairs in one fixed order (no deadlock).
  std::vector<std::int64_t> dims{0};
  for (std::size_t i = 0; i < I; ++i)
    if (!own[i].empty()) dims[0] = own[i].cols;
  comm.allreduce_max(dims);
  const int D = static_cast<int>(dims[0]);
  const auto [lo, hi] = features::kmeans_rows_of_rank(N, rank, ranks);
  cv::Mat block(static_cast<int>(hi - lo), D, CV_32F);
  const auto rows_for = [&](int q, int r,
                            const std::function<void(std::size_t, int, std::int64_t)>& f) {
    // f(image, row of the image, global row) for the rows of q's images in r's block.
    const auto [rlo, rhi] = features::kmeans_rows_of_rank(N, r, ranks);
    for (std::size_t i = static_cast<std::size_t>(q); i < I; i += static_cast<std::size_t>(ranks)) {
      if (offset[i + 1] <= rlo || offset[i] >= rhi) continue;
      for (std::int64_t g = std::max(offset[i], rlo); g < std::min(offset[i + 1], rhi); ++g)
        f(i, static_cast<int>(g - offset[i]), g);
    }
  };
  for (int q = 0; q < ranks; ++q) {
    for (int r = 0; r < ranks; ++r) {
      if (rank != q && rank != r) continue;
      std::vector<float> buffer;
      std::vector<std::int64_t> where;
      rows_for(q, r, [&](std::size_t i, int k, std::int64_t g) {
        where.push_back(g);
        if (rank == q) {
          const float* p = own[i].ptr<float>(picked[i][static_cast<std::size_t>(k)]);
          buffer.insert(buffer.end(), p, p + D);
        }
      });
      if (q == r) {
        for (std::size_t j = 0; j < where.size(); ++j)
          std::copy_n(buffer.data() + j * static_cast<std::size_t>(D), D,
                      block.ptr<float>(static_cast<int>(where[j] - lo)));
        continue;
      }
      if (where.empty()) continue;
      if (rank == q) {
        comm.send(std::as_bytes(std::span(buffer)), r);
      } else {
        buffer.resize(where.size() * static_cast<std::size_t>(D));
        comm.receive(std::as_writable_bytes(std::span(buffer)), q);
        for (std::size_t j = 0; j < where.size(); ++j)
          std::copy_n(buffer.data() + j * static_cast<std::size_t>(D), D,
                      block.ptr<float>(static_cast<int>(where[j] - lo)));
      }
    }
  }
  own.clear();
  // 4. k-means over the ranks.
  VocabularyResult v = build_vocabulary(DescriptorBlock{block, lo, N}, options.kmeans, comm);
  VocabularyBuildResult r{std::move(v.vocabulary),
                          v.summary,
                          set.classes.size(),
                          I,
                          without,
                          static_cast<int>(N),
                          extract_seconds,
                          {},
                          {},
                          core::Json(),
                          {}};
  core::agree(comm, [&] {
    if (rank == 0 && !options.out.empty()) write_vocabulary(options.out, r.vocabulary, provenance);
  });
  r.ranks = ranks;
  fill_document(options, provenance, r);
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace proprio::features
