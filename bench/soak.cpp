// Soak (issue 16): a long generated stream through streaming Motion-Likelihood segmentation and
// online LDA, with the process's resident memory sampled as it goes. Memory must stay flat: after
// the first 10% of the stream, RSS may grow by less than 5% to the end.
//
// usage: soak_stream [--frames N] [--documents N] [--width W] [--height H] [--json FILE]
// (defaults: 100,000 frames at 160 x 120, 100,000 documents). Not a Google Benchmark: one long
// run, its figures in docs/results/reliability.md.
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/random.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/synthetic.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// Resident set size, KiB (VmRSS of /proc/self/status).
long rss_kib() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      long v = 0;
      in >> v;
      return v;
    }
    in.ignore(1 << 20, '\n');
  }
  return -1;
}

struct Sample {
  long at = 0;  // frames or documents done
  long rss = 0;
  double seconds = 0;
};

nlohmann::json summarise(const std::vector<Sample>& s, long total, const char* unit) {
  // RSS after the first 10% against the end: the growth the issue bounds by 5%.
  const Sample* first = &s.front();
  for (const auto& x : s) {
    if (x.at >= total / 10) {
      first = &x;
      break;
    }
  }
  long peak = 0;
  for (const auto& x : s) peak = std::max(peak, x.rss);
  const double growth =
      100.0 * static_cast<double>(s.back().rss - first->rss) / static_cast<double>(first->rss);
  nlohmann::json j;
  j["unit"] = unit;
  j["count"] = total;
  j["seconds"] = s.back().seconds;
  j["rss_kib_at_10_percent"] = first->rss;
  j["rss_kib_at_end"] = s.back().rss;
  j["rss_kib_peak"] = peak;
  j["growth_percent_after_10_percent"] = growth;
  j["flat"] = growth < 5.0;
  nlohmann::json samples = nlohmann::json::array();
  for (const auto& x : s) samples.push_back({x.at, x.rss, x.seconds});
  j["samples_at_rss_kib_seconds"] = samples;
  std::printf(
      "%s: %ld in %.0f s; RSS %ld KiB at 10%%, %ld KiB at the end (%+.2f%%), peak %ld KiB\n", unit,
      total, s.back().seconds, first->rss, s.back().rss, growth, peak);
  return j;
}

// A textured square pushed round a circle over a textured table, the arm's tip at its trailing
// edge: the stream never ends a push, so every frame carries evidence.
nlohmann::json soak_segmentation(long frames, int width, int height) {
  proprio::core::Rng rng(7);
  cv::Mat background(height, width, CV_8UC3);
  cv::Mat object(height / 3, height / 3, CV_8UC3);
  for (cv::Mat* m : {&background, &object}) {
    for (int y = 0; y < m->rows; ++y) {
      for (int x = 0; x < m->cols; ++x) {
        const int g = static_cast<int>(rng.uniform(0, 255));
        m->at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>(g), static_cast<uchar>(255 - g),
                                           static_cast<uchar>((g * 7) % 256));
      }
    }
  }
  cv::GaussianBlur(background, background, cv::Size(5, 5), 1.5);
  proprio::segmentation::MlOptions o;
  o.stream_maps = false;
  o.keep_frame_labels = false;  // a stream keeps no per-frame history
  proprio::segmentation::MlSegmenter seg(o, background.size());
  std::vector<Sample> samples;
  const auto start = Clock::now();
  const long every = std::max(1L, frames / 200);
  cv::Mat frame;
  for (long i = 0; i < frames; ++i) {
    const double a = 2 * M_PI * static_cast<double>(i % 400) / 400.0;
    const double cx = width / 2.0 + width / 4.0 * std::cos(a);
    const double cy = height / 2.0 + height / 5.0 * std::sin(a);
    background.copyTo(frame);
    const int ox = static_cast<int>(cx) - object.cols / 2;
    const int oy = static_cast<int>(cy) - object.rows / 2;
    object.copyTo(frame(cv::Rect(ox, oy, object.cols, object.rows)));
    const Eigen::Vector2d ee(cx - std::sin(a) * object.cols / 2.0,
                             cy + std::cos(a) * object.rows / 2.0);
    (void)seg.push(frame, ee, i >= 2);
    if (i % every == 0 || i + 1 == frames) {
      samples.push_back(
          {i + 1, rss_kib(), std::chrono::duration<double>(Clock::now() - start).count()});
    }
  }
  auto j = summarise(samples, frames, "frames");
  j["width"] = width;
  j["height"] = height;
  j["tracks"] = seg.summary().tracks;
  j["tracks_kept"] = seg.summary().tracks_kept;
  return j;
}

// Online LDA fed mini-batches of freshly drawn documents for ever (as a robot makes a document
// per frame): K = 20 topics over W = 1,000 words, batches of 64.
nlohmann::json soak_lda(long documents) {
  proprio::topics::OnlineLdaOptions o;
  o.num_topics = 20;
  o.batch_size = 64;
  o.seed = 3;
  o.threads = 1;
  proprio::topics::OnlineLda lda(o, 1000, documents);
  std::vector<Sample> samples;
  const auto start = Clock::now();
  const long batches = (documents + o.batch_size - 1) / o.batch_size;
  const long every = std::max(1L, batches / 200);
  long done = 0;
  for (long b = 0; b < batches; ++b) {
    proprio::topics::SyntheticCorpusOptions s;
    s.num_topics = 20;
    s.num_words = 1000;
    s.num_documents = static_cast<int>(std::min<long>(o.batch_size, documents - done));
    s.mean_length = 80;
    s.seed = 1000 + static_cast<std::uint64_t>(b);
    const auto corpus = proprio::topics::make_synthetic_corpus(s).corpus;
    (void)lda.update(corpus, 0, corpus.num_documents());
    done += s.num_documents;
    if (b % every == 0 || b + 1 == batches) {
      samples.push_back(
          {done, rss_kib(), std::chrono::duration<double>(Clock::now() - start).count()});
    }
  }
  return summarise(samples, documents, "documents");
}

}  // namespace

int main(int argc, char** argv) {
  long frames = 100000;
  long documents = 100000;
  int width = 160;
  int height = 120;
  std::string json;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const char* v = argv[i + 1];
    if (k == "--frames") {
      frames = std::atol(v);
    } else if (k == "--documents") {
      documents = std::atol(v);
    } else if (k == "--width") {
      width = std::atoi(v);
    } else if (k == "--height") {
      height = std::atoi(v);
    } else if (k == "--json") {
      json = v;
    } else {
      std::fprintf(stderr, "soak_stream: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (frames < 10 || documents < 10 || width < 64 || height < 48) {
    std::fprintf(stderr,
                 "soak_stream: need frames, documents >= 10 and an image of 64 x 48 at least\n");
    return 2;
  }
  nlohmann::json out;
  out["format"] = "proprio.soak";
  out["lda"] = soak_lda(documents);
  out["segmentation"] = soak_segmentation(frames, width, height);
  if (!json.empty()) proprio::core::write_json_atomic(json, out);
  const bool flat = out["lda"]["flat"].get<bool>() && out["segmentation"]["flat"].get<bool>();
  std::printf("memory %s\n", flat ? "flat (growth < 5% after the first 10%)" : "NOT flat");
  return flat ? 0 : 1;
}
