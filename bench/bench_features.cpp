// Visual-vocabulary speed in the thesis setting (6.3.1): dense SIFT from the opencv-doc images,
// 400 words from 300,000 descriptors by k-means, against OpenCV's cv::kmeans (and, when
// python3-sklearn is installed, scikit-learn's KMeans through bench/bench_kmeans.py) in the
// same run; then nearest-word quantisation with 10,000 words, exact against FLANN's kd-trees.
//
// usage: bench_features [--descriptors 300000] [--words 400] [--threads 2] [--iterations 20]
//                       [--quantize-words 10000] [--no-sklearn] [--json F]
// Costs are all recomputed the same way: the sum of squared distances of every descriptor to
// its nearest word (features::kmeans_cost).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/flann.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "nearest.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/sift.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using proprio::features::kmeans_cost;

namespace {

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string arg(int argc, char** argv, const std::string& name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (argv[i] == name) return argv[i + 1];
  }
  return fallback;
}
bool flag(int argc, char** argv, const std::string& name) {
  for (int i = 1; i < argc; ++i) {
    if (argv[i] == name) return true;
  }
  return false;
}

void write_npy(const fs::path& path, const cv::Mat& m) {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                       std::to_string(m.rows) + ", " + std::to_string(m.cols) + "), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream f(path, std::ios::binary);
  f.write("\x93NUMPY\x01\x00", 8);
  const auto len = static_cast<std::uint16_t>(header.size());
  f.write(reinterpret_cast<const char*>(&len), 2);
  f << header;
  f.write(reinterpret_cast<const char*>(m.data), static_cast<std::streamsize>(m.total() * 4));
}

}  // namespace

int main(int argc, char** argv) {
  const int want = std::stoi(arg(argc, argv, "--descriptors", "300000"));
  const int words = std::stoi(arg(argc, argv, "--words", "400"));
  const int threads = std::stoi(arg(argc, argv, "--threads", "2"));
  const int iterations = std::stoi(arg(argc, argv, "--iterations", "20"));
  const int qwords = std::stoi(arg(argc, argv, "--quantize-words", "10000"));
  const std::string json_out = arg(argc, argv, "--json", "");
  nlohmann::json out;
  out["threads"] = threads;
  out["kernel"] = proprio::features::detail::nearest_kernel_name();
  cv::setNumThreads(threads);

  // 1. Dense SIFT (step 8 px, 16 px patches) on every opencv-doc photograph.
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(PROPRIO_OPENCV_SAMPLES)) {
    const auto ext = e.path().extension().string();
    if (ext == ".jpg" || ext == ".png") images.push_back(e.path());
  }
  std::sort(images.begin(), images.end());
  std::vector<cv::Mat> all;
  std::size_t total = 0;
  double extract_seconds = 0;
  for (const auto& p : images) {
    const cv::Mat img = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
    if (img.empty()) continue;
    const auto t0 = Clock::now();
    auto f = proprio::features::dense_sift(img, {});
    extract_seconds += since(t0);
    if (f.empty()) continue;
    total += static_cast<std::size_t>(f.descriptors.rows);
    all.push_back(f.descriptors);
  }
  cv::Mat everything;
  cv::vconcat(all, everything);
  std::printf(
      "dense SIFT: %zu images, %zu descriptors in %.2f s = %.0f descriptors/s (%d threads)\n",
      all.size(), total, extract_seconds, static_cast<double>(total) / extract_seconds, threads);
  out["dense_sift"] = {{"images", all.size()},
                       {"descriptors", total},
                       {"seconds", extract_seconds},
                       {"descriptors_per_s", static_cast<double>(total) / extract_seconds}};

  // A fixed random subset of `want` descriptors (all of them if fewer).
  proprio::core::Rng rng(7);
  std::vector<int> idx(static_cast<std::size_t>(everything.rows));
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  for (std::size_t i = 0; i + 1 < idx.size(); ++i) {
    std::swap(idx[i], idx[i + rng.index(idx.size() - i)]);
  }
  idx.resize(std::min<std::size_t>(idx.size(), static_cast<std::size_t>(want)));
  cv::Mat data(static_cast<int>(idx.size()), everything.cols, CV_32F);
  for (std::size_t i = 0; i < idx.size(); ++i)
    everything.row(idx[i]).copyTo(data.row(static_cast<int>(i)));
  everything.release();
  std::printf("k-means: %d descriptors into %d words, %d threads, kernel %s\n", data.rows, words,
              threads, proprio::features::detail::nearest_kernel_name().c_str());
  out["kmeans"]["descriptors"] = data.rows;
  out["kmeans"]["words"] = words;

  auto report = [&](const std::string& name, double seconds, int iters, double cost) {
    std::printf("  %-34s %8.2f s  %3d iterations  cost %.6e\n", name.c_str(), seconds, iters, cost);
    out["kmeans"]["runs"].push_back(
        {{"name", name}, {"seconds", seconds}, {"iterations", iters}, {"cost", cost}});
  };

  // 2. proprio, default stopping rule (0.1% change), and exactly `iterations` iterations.
  {
    proprio::features::KmeansOptions o;
    o.words = words;
    o.threads = threads;
    const auto r = proprio::features::build_vocabulary(data, o);
    report("proprio (stop below 0.1%)", r.summary.seconds, r.summary.iterations,
           kmeans_cost(r.vocabulary, data, threads));
    o.max_iterations = iterations;
    o.tolerance = 0;
    const auto r2 = proprio::features::build_vocabulary(data, o);
    report("proprio (" + std::to_string(iterations) + " iterations)", r2.summary.seconds,
           r2.summary.iterations, kmeans_cost(r2.vocabulary, data, threads));
  }
  // 3. OpenCV's kmeans: k-means++ centres, one attempt, `iterations` iterations.
  if (!flag(argc, argv, "--no-opencv")) {
    cv::Mat labels;
    cv::Mat centres;
    const auto t0 = Clock::now();
    cv::kmeans(data, words, labels, cv::TermCriteria(cv::TermCriteria::MAX_ITER, iterations, 0), 1,
               cv::KMEANS_PP_CENTERS, centres);
    const double s = since(t0);
    report("cv::kmeans (" + std::to_string(iterations) + " iterations)", s, iterations,
           kmeans_cost(proprio::features::Vocabulary(centres), data, threads));
  }
  // 4. scikit-learn through the peer script, when installed.
  if (!flag(argc, argv, "--no-sklearn")) {
    const fs::path npy = fs::temp_directory_path() / "bench_features_descriptors.npy";
    const fs::path res = fs::temp_directory_path() / "bench_features_sklearn.json";
    write_npy(npy, data);
    // The peer script beside this program's source, found from the build layout (no absolute
    // path of the tree compiled in).
    const fs::path script = fs::read_symlink("/proc/self/exe").parent_path() /
                            PROPRIO_BENCH_SOURCE_FROM_BIN / "bench" / "bench_kmeans.py";
    const std::string cmd = "/usr/bin/python3 " + script.string() + " " + npy.string() +
                            " --words " + std::to_string(words) + " --iterations " +
                            std::to_string(iterations) + " --threads " + std::to_string(threads) +
                            " --out " + res.string();
    if (std::system(cmd.c_str()) == 0) {
      std::ifstream f(res);
      const auto j = nlohmann::json::parse(f);
      cv::Mat c(words, data.cols, CV_32F);
      const auto& v = j["centres"];
      for (int k = 0; k < words; ++k) {
        for (int d = 0; d < data.cols; ++d)
          c.at<float>(k, d) =
              v[static_cast<std::size_t>(k)][static_cast<std::size_t>(d)].get<float>();
      }
      report("scikit-learn KMeans (" + std::to_string(j["iterations"].get<int>()) + ")",
             j["seconds"].get<double>(), j["iterations"].get<int>(),
             kmeans_cost(proprio::features::Vocabulary(c), data, threads));
    } else {
      std::printf("  scikit-learn: skipped (python3-sklearn not installed?)\n");
    }
    fs::remove(npy);
    fs::remove(res);
  }

  // 5. Quantisation with `qwords` words (descriptors as words): exact kernel vs FLANN.
  {
    const int nq = std::min(data.rows, 100000);
    const cv::Mat w = data.rowRange(0, qwords).clone();
    const cv::Mat q = data.rowRange(data.rows - nq, data.rows);
    const proprio::features::Vocabulary v(w);
    auto t0 = Clock::now();
    const auto exact = v.quantize(q, threads);
    const double te = since(t0);
    std::printf("quantise %d descriptors to %d words: exact %.3f s (%.0f descriptors/s)\n", nq,
                qwords, te, nq / te);
    out["quantize"] = {{"words", qwords}, {"descriptors", nq}, {"exact_seconds", te}};
    t0 = Clock::now();
    cv::flann::Index index(w, cv::flann::KDTreeIndexParams(4));
    const double tb = since(t0);
    for (const int checks : {32, 128}) {
      cv::Mat ids;
      cv::Mat dists;
      t0 = Clock::now();
      index.knnSearch(q, ids, dists, 1, cv::flann::SearchParams(checks));
      const double tf = since(t0);
      int agree = 0;
      for (int i = 0; i < nq; ++i) agree += ids.at<int>(i) == exact[static_cast<std::size_t>(i)];
      std::printf("  FLANN 4 kd-trees, %3d checks: build %.2f s, search %.3f s, %.1f%% exact\n",
                  checks, tb, tf, 100.0 * agree / nq);
      out["quantize"]["flann"].push_back({{"checks", checks},
                                          {"build_seconds", tb},
                                          {"search_seconds", tf},
                                          {"agree_with_exact", static_cast<double>(agree) / nq}});
    }
  }
  if (!json_out.empty()) std::ofstream(json_out) << out.dump(2) << "\n";
  return 0;
}
