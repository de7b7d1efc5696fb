// Online and batch LDA on corpora drawn from known topics: the topics come back, held-out
// perplexity falls, the two agree, results repeat, distributions are distributions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hungarian.hpp"
#include "proprio/core/error.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/perplexity.hpp"
#include "proprio/topics/synthetic.hpp"
#include "proprio/topics/topic_distance.hpp"

namespace proprio::topics {
namespace {

struct Recovery {
  double median = 1.0;
  double within = 0.0;  ///< fraction of topics matched within 0.1
  std::vector<double> distances;
};

Recovery recovery(const Eigen::MatrixXd& truth, const Eigen::MatrixXd& learned) {
  const Eigen::MatrixXd h = hellinger_matrix(truth, learned);
  const auto match = test::min_cost_assignment(h);
  Recovery r;
  if (match.empty()) return r;
  for (long i = 0; i < h.rows(); ++i)
    r.distances.push_back(h(i, match[static_cast<std::size_t>(i)]));
  auto sorted = r.distances;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  r.median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  r.within = static_cast<double>(
                 std::count_if(sorted.begin(), sorted.end(), [](double d) { return d < 0.1; })) /
             static_cast<double>(n);
  return r;
}

// One shared synthetic corpus: 10 topics over 400 words, 2500 documents of ~120 tokens.
const SyntheticCorpus& synthetic() {
  static const SyntheticCorpus s = [] {
    SyntheticCorpusOptions o;
    o.num_topics = 10;
    o.num_words = 400;
    o.num_documents = 2500;
    o.mean_length = 120;
    o.alpha = 0.1;
    o.eta = 0.05;
    o.seed = 7;
    return make_synthetic_corpus(o);
  }();
  return s;
}

const CorpusSplit& split() {
  static const CorpusSplit s = hold_out(synthetic().corpus, 0.1, 3);
  return s;
}

OnlineLdaOptions online_options() {
  OnlineLdaOptions o;
  o.num_topics = 10;
  o.batch_size = 100;
  o.tau0 = 1.0;
  o.kappa = 0.7;
  o.alpha = 0.1;
  o.eta = 0.05;
  o.passes = 10;
  o.seed = 11;
  o.evaluate_every = 10;
  return o;
}

const OnlineLdaResult& online() {
  static const OnlineLdaResult r =
      train_online_lda(split().train, split().heldout, online_options());
  return r;
}

const BatchLdaResult& batch() {
  static const BatchLdaResult r = [] {
    BatchLdaOptions o;
    o.num_topics = 10;
    o.alpha = 0.1;
    o.eta = 0.05;
    o.max_iterations = 60;
    o.seed = 11;
    return train_batch_lda(split().train, o);
  }();
  return r;
}

TEST(OnlineLda, RecoversTheTopicsThatMadeTheCorpus) {
#ifndef PROPRIO_HAVE_DLIB
  GTEST_SKIP() << "dlib (libdlib-dev) is not installed";
#endif
  const Recovery r = recovery(synthetic().topics, online().model.topic_word());
  EXPECT_LT(r.median, 0.1);
  EXPECT_GE(r.within, 0.75) << ::testing::PrintToString(r.distances);
}

TEST(BatchLda, RecoversTheTopicsThatMadeTheCorpus) {
#ifndef PROPRIO_HAVE_DLIB
  GTEST_SKIP() << "dlib (libdlib-dev) is not installed";
#endif
  const Recovery r = recovery(synthetic().topics, batch().model.topic_word());
  EXPECT_LT(r.median, 0.1);
  EXPECT_GE(r.within, 0.75) << ::testing::PrintToString(r.distances);
  EXPECT_GT(batch().summary.iterations, 1);
}

TEST(OnlineLda, HeldOutPerplexityFallsAsMiniBatchesArrive) {
  const auto& trace = online().summary.trace;
  ASSERT_GE(trace.size(), 5u);
  EXPECT_EQ(trace.front().updates, 0);
  EXPECT_EQ(trace.back().updates, online().summary.updates);
  // The random start is near-uniform (perplexity near W); training brings it far down, and the
  // second half of training is no worse than the first half's end.
  EXPECT_GT(trace.front().perplexity, 300.0);
  EXPECT_LT(trace.back().perplexity, 0.5 * trace.front().perplexity);
  EXPECT_LT(trace[1].perplexity, trace.front().perplexity);
  EXPECT_LE(trace.back().perplexity, trace[trace.size() / 2].perplexity * 1.01);
  for (std::size_t i = 1; i < trace.size(); ++i) {
    EXPECT_GT(trace[i].updates, trace[i - 1].updates);
    EXPECT_GT(trace[i].documents_seen, trace[i - 1].documents_seen);
  }
}

TEST(OnlineLda, AgreesWithBatchLdaOnHeldOutPerplexity) {
  const double po = perplexity(online().model, split().heldout).perplexity;
  const double pb = perplexity(batch().model, split().heldout).perplexity;
  EXPECT_NEAR(po / pb, 1.0, 0.05) << "online " << po << ", batch " << pb;
  EXPECT_NEAR(online().summary.trace.back().perplexity, po, 1e-9 * po);
}

TEST(BatchLda, BoundRisesAndConverges) {
  const auto& b = batch().summary.bound;
  ASSERT_GE(b.size(), 3u);
  EXPECT_GT(b.back(), b.front());
  // Variational EM never lowers the bound (up to float round-off in the E-step).
  for (std::size_t i = 2; i < b.size(); ++i) EXPECT_GT(b[i], b[i - 1] - 1e-4 * std::abs(b[i - 1]));
}

TEST(OnlineLda, SameSeedSameModelAndThreadsDoNotChangeIt) {
  OnlineLdaOptions o = online_options();
  o.passes = 1;
  o.evaluate_every = 0;
  const auto a = train_online_lda(split().train, o);
  const auto b = train_online_lda(split().train, o);
  EXPECT_TRUE(a.model == b.model);
  o.threads = 2;
  const auto c = train_online_lda(split().train, o);
  EXPECT_TRUE(a.model == c.model) << "2 threads differ from 1";
  o.threads = 1;
  o.seed = 12;
  const auto d = train_online_lda(split().train, o);
  EXPECT_FALSE(a.model == d.model);
}

TEST(OnlineLda, DistributionsSumToOne) {
  const Eigen::MatrixXd beta = online().model.topic_word();
  for (Eigen::Index k = 0; k < beta.rows(); ++k) {
    EXPECT_NEAR(beta.row(k).sum(), 1.0, 1e-12);
    EXPECT_GT(beta.row(k).minCoeff(), 0.0);
  }
  const InferenceResult inf = infer_topics(online().model, split().heldout);
  const Eigen::MatrixXd theta = inf.theta();
  ASSERT_EQ(theta.rows(), static_cast<Eigen::Index>(split().heldout.num_documents()));
  for (Eigen::Index d = 0; d < theta.rows(); ++d) {
    EXPECT_NEAR(theta.row(d).sum(), 1.0, 1e-12);
    // gamma = alpha + expected counts: it sums to K alpha + the document's tokens (eq B.17).
    EXPECT_NEAR(inf.gamma.row(d).sum(),
                10 * 0.1 + static_cast<double>(inf.tokens[static_cast<std::size_t>(d)]),
                1e-3 * inf.gamma.row(d).sum());
  }
}

TEST(Inference, ClassifiesByTheMostProbableTopicAndLeavesEmptyDocumentsUnclassified) {
  const LdaModel& m = online().model;
  Corpus c(m.num_words());
  // A document made of topic k's top words belongs to topic k.
  for (int k = 0; k < m.num_topics(); ++k) {
    const auto top = m.top_words(k, 5);
    std::vector<std::int32_t> ids(top.begin(), top.end());
    std::vector<std::int32_t> counts(ids.size(), 20);
    c.add_document(ids, counts);
  }
  c.add_document({}, {});
  const InferenceResult r = infer_topics(m, c);
  const auto cls = r.classify();
  for (int k = 0; k < m.num_topics(); ++k) EXPECT_EQ(cls[static_cast<std::size_t>(k)], k);
  EXPECT_EQ(cls.back(), -1);
  EXPECT_EQ(r.summary.empty_documents, 1);
  // The empty document's gamma is the prior: theta uniform.
  EXPECT_NEAR(r.theta().row(m.num_topics()).maxCoeff(), 1.0 / m.num_topics(), 1e-12);
}

TEST(Inference, ThreadsDoNotChangeTheResult) {
  InferenceOptions o;
  const auto a = infer_topics(online().model, split().heldout, o);
  o.threads = 2;
  const auto b = infer_topics(online().model, split().heldout, o);
  EXPECT_TRUE(a.gamma == b.gamma);
}

TEST(Perplexity, BoundIsAboveCompletionOnWellFitData) {
  PerplexityOptions o;
  o.method = PerplexityMethod::kVariationalBound;
  const auto bound = perplexity(online().model, split().heldout, o);
  const auto comp = perplexity(online().model, split().heldout);
  EXPECT_EQ(bound.tokens, split().heldout.num_tokens());
  EXPECT_GT(bound.perplexity, 1.0);
  EXPECT_TRUE(std::isfinite(bound.perplexity));
  // Both are far better than a uniform model's W = 400.
  EXPECT_LT(bound.perplexity, 400.0);
  EXPECT_LT(comp.perplexity, 400.0);
}

TEST(Perplexity, CompletionSplitKeepsEveryTokenOnce) {
  const Corpus& c = split().heldout;
  const CompletionSplit s = split_for_completion(c, 5);
  ASSERT_EQ(s.observed.num_documents(), c.num_documents());
  EXPECT_EQ(s.observed.num_tokens() + s.scored.num_tokens(), c.num_tokens());
  for (std::size_t d = 0; d < c.num_documents(); ++d) {
    const auto n = c.document(d).tokens();
    EXPECT_EQ(s.observed.document(d).tokens(), n / 2);
  }
  EXPECT_TRUE(split_for_completion(c, 5).observed == s.observed);
  EXPECT_FALSE(split_for_completion(c, 6).observed == s.observed);
}

TEST(Perplexity, UniformTopicsGivePerplexityW) {
  LdaModel m;
  m.lambda = Eigen::MatrixXd::Constant(3, 50, 2.0);
  m.alpha = 0.5;
  m.eta = 0.5;
  Corpus c(50);
  std::vector<std::int32_t> t{1, 2, 3, 4, 5, 6, 7, 8, 9, 9};
  c.add_tokens(t);
  EXPECT_NEAR(perplexity(m, c).perplexity, 50.0, 1e-6);
}

TEST(Perplexity, RejectsMismatchedOrEmptyCorpora) {
  const LdaModel& m = online().model;
  Corpus wrong(m.num_words() + 1);
  wrong.add_tokens(std::vector<std::int32_t>{1, 2});
  EXPECT_THROW(perplexity(m, wrong), Error);
  Corpus empty(m.num_words());
  empty.add_document({}, {});
  EXPECT_THROW(perplexity(m, empty), Error);
}

TEST(OnlineLda, StreamingUpdatesMatchTraining) {
  OnlineLdaOptions o = online_options();
  o.passes = 1;
  o.evaluate_every = 0;
  const Corpus& c = split().train;
  OnlineLda lda(o, c.num_words(), static_cast<std::int64_t>(c.num_documents()));
  for (std::size_t b = 0; b < c.num_documents(); b += 100) {
    const auto st = lda.update(c, b, std::min(c.num_documents(), b + 100));
    EXPECT_GT(st.rho, 0.0);
    EXPECT_LE(st.rho, 1.0);
  }
  EXPECT_TRUE(lda.model() == train_online_lda(c, o).model);
  EXPECT_EQ(lda.model().updates, static_cast<std::int64_t>((c.num_documents() + 99) / 100));
}

TEST(OnlineLda, RejectsBadOptions) {
  OnlineLdaOptions o;
  o.kappa = 0.5;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.num_topics = 0;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.batch_size = 0;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.alpha = -1;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.estep.max_iterations = 0;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.estep.tolerance = std::nan("");
  EXPECT_THROW(o.validate(), Error);
  EXPECT_NO_THROW(OnlineLdaOptions{}.validate());
}

TEST(OnlineLda, EmptyDocumentsAreAllowed) {
  Corpus c(20);
  c.add_document({}, {});
  c.add_tokens(std::vector<std::int32_t>{1, 2, 3, 3});
  c.add_document({}, {});
  OnlineLdaOptions o;
  o.num_topics = 3;
  o.batch_size = 2;
  const auto r = train_online_lda(c, o);
  EXPECT_NO_THROW(r.model.validate());
  EXPECT_EQ(r.summary.documents, 3);
  EXPECT_EQ(r.summary.tokens, 4);
}

}  // namespace
}  // namespace proprio::topics
