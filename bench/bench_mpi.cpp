// The measured constants (processor time, one thread) of the strong-scaling model of data-parallel
// online LDA (issue 23, docs/results/mpi.md; bench/bench_mpi_model.py projects them): on this
// machine, one thread,
//  - the E-step per document (K topics, the first mini-batches of a real corpus, the man pages),
//    exp E[log beta] per (batch word x topic), the sufficient statistics per (entry x topic);
//  - the M-step per (word x topic) of lambda (the update touches every word: its decay);
//  - the combination of statistics: adding one float32 and one float64 array of K x W into
//    another, per element (what a reduction does per element besides sending it).
// usage: bench_mpi CORPUS_DIR [K ...]   (UCI corpus, e.g. make-manpage-corpus's train/); JSON on
// stdout.
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "engine.hpp"
#include "kernels.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/random.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::topics {
namespace {

// Processor time of the process (one thread computes): the machine is shared, and its other
// users' load would inflate wall-clock times.
double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The best of `repeats` processor times of f().
template <class F>
double best_of(int repeats, F&& f) {
  double best = 1e300;
  for (int i = 0; i < repeats; ++i) {
    const double t0 = cpu_now();
    f();
    best = std::min(best, cpu_now() - t0);
  }
  return best;
}

core::Json measure(const Corpus& corpus, int K, int batch) {
  const detail::Kernels& kern = detail::best_kernels();
  core::ThreadPool pool(1);
  const int stride = detail::padded(K, kern.lanes);
  // A model trained on the first `trained` documents (one pass), so that the E-step runs as it
  // does in the middle of training, not on the random start (where it hits its iteration cap).
  const std::size_t trained = std::min<std::size_t>(corpus.num_documents() / 2, 16 * batch);
  OnlineLdaOptions train;
  train.num_topics = K;
  train.batch_size = batch;
  train.threads = 1;
  OnlineLda learner(train, corpus.num_words(), static_cast<std::int64_t>(corpus.num_documents()));
  for (std::size_t b = 0; b + static_cast<std::size_t>(batch) <= trained; b += batch)
    (void)learner.update(corpus, b, b + static_cast<std::size_t>(batch));
  const Eigen::MatrixXd& lambda = learner.model().lambda;
  const Eigen::VectorXd topic_sum = detail::topic_sums(lambda, pool);
  // The next mini-batches of the corpus, built as OnlineLda builds them.
  core::Json out;
  double estep = 0, beta = 0, sstats = 0;
  std::int64_t docs = 0, entries = 0, rows = 0, iterations = 0, batches = 0;
  const std::size_t n = std::min<std::size_t>(corpus.num_documents(), trained + 4 * batch);
  for (std::size_t b = trained; b + static_cast<std::size_t>(batch) <= n; b += batch) {
    std::vector<std::int32_t> row_of(static_cast<std::size_t>(corpus.num_words()), -1);
    std::vector<std::int32_t> words;
    detail::BatchDocs d;
    for (std::size_t i = b; i < b + static_cast<std::size_t>(batch); ++i) {
      const auto doc = corpus.document(i);
      for (std::size_t j = 0; j < doc.size(); ++j) {
        std::int32_t& r = row_of[static_cast<std::size_t>(doc.words[j])];
        if (r < 0) {
          r = static_cast<std::int32_t>(words.size());
          words.push_back(doc.words[j]);
        }
        d.rows.push_back(r);
        d.counts.push_back(static_cast<float>(doc.counts[j]));
      }
      d.offsets.push_back(d.rows.size());
      d.keys.push_back(core::stream_seed(1, 0, i));
    }
    detail::FloatBuffer cache;
    detail::BatchEStep e;
    detail::FloatBuffer s;
    beta += best_of(
        3, [&] { detail::exp_elog_beta(kern, lambda, topic_sum, words, stride, pool, cache); });
    EStepOptions eo{100, 1e-3, GammaInit::kRandomGamma};
    estep += best_of(
        2, [&] { detail::run_estep(kern, pool, d, cache.data(), K, stride, 1.0 / K, eo, e); });
    sstats += best_of(3, [&] { detail::sufficient_statistics(kern, pool, d, e, words.size(), s); });
    for (const int it : e.iterations) iterations += it;
    docs += batch;
    entries += static_cast<std::int64_t>(d.rows.size());
    rows += static_cast<std::int64_t>(words.size());
    ++batches;
  }
  out["K"] = K;
  out["trained_documents"] = trained;
  out["batch"] = batch;
  out["batches_timed"] = batches;
  out["estep_seconds_per_document"] = estep / static_cast<double>(docs);
  out["mean_estep_iterations"] = static_cast<double>(iterations) / static_cast<double>(docs);
  out["entries_per_document"] = static_cast<double>(entries) / static_cast<double>(docs);
  out["batch_words_per_batch"] = static_cast<double>(rows) / static_cast<double>(batches);
  out["beta_seconds_per_word_topic"] = beta / static_cast<double>(rows) / K;
  out["sstats_seconds_per_entry_topic"] = sstats / static_cast<double>(entries) / K;

  // M-step per (word, topic): one update of a model over W = 100,000 words whose mini-batch is
  // one word (the E-step is then nothing; the decay of every word of lambda is all).
  const int W = 100000;
  OnlineLdaOptions o;
  o.num_topics = K;
  o.threads = 1;
  OnlineLda lda(o, W, 3000000);
  Corpus one(W);
  const std::int32_t w = 7;
  const std::int32_t c = 1;
  for (int i = 0; i < 5; ++i) one.add_document({&w, 1}, {&c, 1});
  const double m = best_of(5, [&] { (void)lda.update(one, 0, 1); });
  out["mstep_seconds_per_word_topic"] = m / (static_cast<double>(W) * K);

  // Combining statistics: y += x over K x W elements, float32 and float64.
  const auto kw = static_cast<std::size_t>(K) * W;
  std::vector<float> xf(kw, 1.0f), yf(kw, 0.5f);
  std::vector<double> xd(kw, 1.0), yd(kw, 0.5);
  const double tf = best_of(5, [&] {
    for (std::size_t i = 0; i < kw; ++i) yf[i] += xf[i];
  });
  const double td = best_of(5, [&] {
    for (std::size_t i = 0; i < kw; ++i) yd[i] += xd[i];
  });
  out["combine_float32_seconds_per_element"] = tf / static_cast<double>(kw);
  out["combine_float64_seconds_per_element"] = td / static_cast<double>(kw);
  out["checksum"] = static_cast<double>(yf[kw / 2]) + yd[kw / 3];
  return out;
}

}  // namespace
}  // namespace proprio::topics

int main(int argc, char** argv) {
  using namespace proprio;
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_mpi CORPUS_DIR [K ...]\n");
    return 2;
  }
  try {
    const topics::Corpus corpus = topics::read_corpus(argv[1], topics::CorpusFormat::kUci);
    std::vector<int> ks;
    for (int i = 2; i < argc; ++i) ks.push_back(std::atoi(argv[i]));
    if (ks.empty()) ks = {100, 1000};
    core::Json out;
    out["corpus"] = argv[1];
    out["documents"] = corpus.num_documents();
    out["words"] = corpus.num_words();
    out["tokens"] = corpus.num_tokens();
    out["kernel"] = topics::detail::best_kernels().name;
    out["measurements"] = core::Json::array();
    for (const int k : ks) out["measurements"].push_back(topics::measure(corpus, k, 256));
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mpi: %s\n", e.what());
    return 2;
  }
}
