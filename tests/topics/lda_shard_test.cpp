// Sharded corpus reading and the data-parallel online LDA update on one rank (issue 23): the
// shards of a corpus are its documents d mod n, and the data-parallel path with a world of one
// gives the one-process model bit for bit. Two and three ranks: tests/app/mpi_cli_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <utility>
#include <vector>

#include "../support/named_corpus.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/communicator.hpp"
#include "proprio/core/error.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::topics {
namespace {

// The options of the single-rank comparisons: K topics, mini-batches of 16, seed 3, 2 threads.
OnlineLdaOptions one_rank_options(int K, int passes) {
  OnlineLdaOptions o;
  o.num_topics = K;
  o.batch_size = 16;
  o.passes = passes;
  o.seed = 3;
  o.threads = 2;
  return o;
}

Corpus small_corpus() {
  SyntheticCorpusOptions o;
  o.num_topics = 4;
  o.num_words = 60;
  o.num_documents = 103;
  o.mean_length = 30;
  o.seed = 5;
  const Corpus c = test::named_synthetic_corpus(o);
  // With an empty document, which the shards must keep in place.
  Corpus out(c.num_words(), c.vocabulary());
  for (std::size_t d = 0; d < c.num_documents(); ++d) {
    if (d == 10) out.add_document({}, {});
    out.add_document(c.document(d).words, c.document(d).counts);
  }
  return out;
}

class CorpusShards : public ::testing::TestWithParam<CorpusFormat> {};

TEST_P(CorpusShards, ShardsAreTheDocumentsModuloTheirCount) {
  const test::TempDir dir("proprio_shard_");
  const Corpus c = small_corpus();
  write_corpus(c, dir.path(), GetParam());
  for (const int n : {1, 2, 3, 7}) {
    std::uint64_t checksum = 0;
    for (int s = 0; s < n; ++s) {
      const CorpusShard shard = read_corpus_shard(dir.path(), GetParam(), s, n);
      EXPECT_EQ(shard.total_documents, static_cast<std::int64_t>(c.num_documents()));
      EXPECT_EQ(shard.total_tokens, c.num_tokens());
      EXPECT_EQ(shard.documents.num_words(), c.num_words());
      EXPECT_EQ(shard.documents.vocabulary(), c.vocabulary());
      std::vector<std::size_t> mine;
      for (std::size_t d = static_cast<std::size_t>(s); d < c.num_documents(); d += n) {
        mine.push_back(d);
      }
      EXPECT_EQ(shard.documents, c.subset(mine)) << s << " of " << n;
      EXPECT_EQ(shard.global_index(1), static_cast<std::size_t>(s + n));
      EXPECT_EQ(shard.first_local_at(static_cast<std::size_t>(s + n)), 1u);
      EXPECT_EQ(shard.first_local_at(static_cast<std::size_t>(s + n + 1)), 2u);
      if (s > 0) {
        EXPECT_EQ(shard.checksum, checksum);
      }
      checksum = shard.checksum;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, CorpusShards,
                         ::testing::Values(CorpusFormat::kUci, CorpusFormat::kLdac));

TEST(CorpusShards, BadInputIsFoundByEveryShardAndMatrixMarketIsRefused) {
  const test::TempDir dir("proprio_shard_");
  const auto f = dir.path() / "docword.txt";
  {
    std::ofstream out(f);
    out << "2\n3\n2\n1 1 1\n2 4 1\n";  // word 4 of 3, in shard 1's document
    std::ofstream(dir.path() / "vocab.txt") << "a\nb\nc\n";
  }
  for (int s = 0; s < 2; ++s) {
    try {
      (void)read_corpus_shard(f, CorpusFormat::kUci, s, 2);
      FAIL() << "no error in shard " << s;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("docword.txt:5: wordID 4 outside [1, 3]"),
                std::string::npos)
          << e.what();
    }
  }
  write_corpus(small_corpus(), dir.path() / "mm", CorpusFormat::kMatrixMarket);
  EXPECT_THROW((void)read_corpus_shard(dir.path() / "mm", CorpusFormat::kMatrixMarket, 0, 2),
               Error);
}

TEST(DataParallelLda, OneRankGivesTheOneProcessModelBitForBit) {
  const test::TempDir dir("proprio_shard_");
  const Corpus c = small_corpus();
  write_corpus(c, dir.path(), CorpusFormat::kUci);
  const OnlineLdaOptions o = one_rank_options(5, 2);
  const OnlineLdaResult one = train_online_lda(c, o);
  core::LocalCommunicator world;
  const CorpusShard shard = read_corpus_shard(dir.path(), CorpusFormat::kUci, 0, 1);
  const OnlineLdaResult par = train_online_lda(shard, nullptr, o, world);
  ASSERT_EQ(par.model.lambda.size(), one.model.lambda.size());
  EXPECT_EQ(std::memcmp(par.model.lambda.data(), one.model.lambda.data(),
                        static_cast<std::size_t>(one.model.lambda.size()) * sizeof(double)),
            0);
  EXPECT_EQ(par.model.updates, one.model.updates);
  EXPECT_EQ(par.summary.documents, one.summary.documents);
  EXPECT_EQ(par.summary.tokens, one.summary.tokens);
  EXPECT_EQ(par.summary.mean_estep_iterations, one.summary.mean_estep_iterations);
  EXPECT_EQ(par.summary.capped, one.summary.capped);
}

// The update split by topic rows, on a world of one (the code path of every rank of a by-topic
// job: its rows' exp E[log beta], statistics and M-step, then gather_topics): the one-process
// model bit for bit, with an odd K and a vocabulary longer than one 512-word block of the sums.
TEST(DataParallelLda, ByTopicOnOneRankGivesTheOneProcessModelBitForBit) {
  const test::TempDir dir("proprio_shard_");
  SyntheticCorpusOptions co;
  co.num_topics = 3;
  co.num_words = 700;
  co.num_documents = 90;
  co.mean_length = 40;
  co.seed = 9;
  const Corpus c = test::named_synthetic_corpus(co);
  write_corpus(c, dir.path(), CorpusFormat::kUci);
  const OnlineLdaOptions o = one_rank_options(7, 1);
  const OnlineLdaResult one = train_online_lda(c, o);
  core::LocalCommunicator world;
  const CorpusShard shard = read_corpus_shard(dir.path(), CorpusFormat::kUci, 0, 1);
  OnlineLda lda(o, c.num_words(), static_cast<std::int64_t>(c.num_documents()), c.vocabulary());
  lda.distribute_by_topic(world);
  for (std::size_t b = 0; b < c.num_documents(); b += 16) {
    lda.update(shard, b, std::min(c.num_documents(), b + 16), world);
  }
  lda.gather_topics(world);
  const Eigen::MatrixXd& got = lda.model().lambda;
  ASSERT_EQ(got.size(), one.model.lambda.size());
  EXPECT_EQ(std::memcmp(got.data(), one.model.lambda.data(),
                        static_cast<std::size_t>(got.size()) * sizeof(double)),
            0);
  EXPECT_EQ(lda.phase_times().updates, one.model.updates);
}

// A model split by topic from the start (each rank draws only its rows of the starting lambda and
// never holds K x W): no lambda until gathered, none after a gather to other ranks, and the
// one-process model bit for bit when gathered here.
TEST(DataParallelLda, SplitFromTheStartHoldsNoWholeLambdaUntilGathered) {
  const test::TempDir dir("proprio_shard_");
  const Corpus c = small_corpus();
  write_corpus(c, dir.path(), CorpusFormat::kUci);
  const OnlineLdaOptions o = one_rank_options(5, 2);
  const OnlineLdaResult one = train_online_lda(c, o);
  core::LocalCommunicator world;
  const CorpusShard shard = read_corpus_shard(dir.path(), CorpusFormat::kUci, 0, 1);
  OnlineLda lda(o, c.num_words(), static_cast<std::int64_t>(c.num_documents()), c.vocabulary(),
                world);
  EXPECT_EQ(lda.model().lambda.size(), 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t b = 0; b < c.num_documents(); b += 16) {
      lda.update(shard, b, std::min(c.num_documents(), b + 16), world);
    }
  }
  lda.gather_topics(world, false);
  EXPECT_EQ(lda.model().lambda.size(), 0);
  lda.gather_topics(world);
  const LdaModel got = lda.release_model();
  ASSERT_EQ(got.lambda.size(), one.model.lambda.size());
  EXPECT_EQ(std::memcmp(got.lambda.data(), one.model.lambda.data(),
                        static_cast<std::size_t>(got.lambda.size()) * sizeof(double)),
            0);
  EXPECT_EQ(got.updates, one.model.updates);
  EXPECT_THROW(lda.update(c, 0, 16), InternalError);  // split by topic: the communicator's update
}

// The lean exchange sends the next batch's documents with this one's E-step output, for the
// range it predicts (the next one of the widest width, from 0 after the end): updates in another
// order (batches of 11, 13, 16, 8 and 7 documents, jumps back and forth) miss the prediction and
// gather their documents first; the model is the one-process model of the same updates bit for
// bit, and the number of collectives shows which batches came ahead.
TEST(DataParallelLda, UpdatesOutOfThePredictedOrderGiveTheOneProcessModel) {
  const test::TempDir dir("proprio_shard_");
  const Corpus c = small_corpus();
  write_corpus(c, dir.path(), CorpusFormat::kUci);
  core::LocalCommunicator world;
  const CorpusShard shard = read_corpus_shard(dir.path(), CorpusFormat::kUci, 0, 1);
  ASSERT_EQ(c.num_documents(), 104U);
  const auto D = static_cast<std::int64_t>(c.num_documents());
  const std::vector<std::pair<std::size_t, std::size_t>> ranges = {
      {0, 16}, {16, 32}, {91, 104}, {0, 16}, {80, 91}, {64, 80}, {80, 96}, {96, 104}, {0, 7}};
  for (const MpiLdaExchange exchange : {MpiLdaExchange::kLean, MpiLdaExchange::kThree}) {
    OnlineLdaOptions o = one_rank_options(5, 1);
    o.mpi.exchange = exchange;
    OnlineLda one(o, c.num_words(), D, c.vocabulary());
    OnlineLda par(o, c.num_words(), D, c.vocabulary());
    for (const auto& [b, e] : ranges) {
      const MiniBatchStats a = one.update(c, b, e);
      const MiniBatchStats p = par.update(shard, b, e, world);
      EXPECT_EQ(p.tokens, a.tokens);
      EXPECT_EQ(p.estep_iterations, a.estep_iterations);
    }
    const Eigen::MatrixXd& want = one.model().lambda;
    ASSERT_EQ(par.model().lambda.size(), want.size());
    EXPECT_EQ(std::memcmp(par.model().lambda.data(), want.data(),
                          static_cast<std::size_t>(want.size()) * sizeof(double)),
              0);
    // Lean: predicted, so the documents came ahead with the E-step output of the update before,
    // of sizes announced the update before that (one MPI call, sizes known): [16, 32) after
    // [0, 16), [0, 16) after [91, 104) (from 0 after the end), [80, 96) after [64, 80),
    // [96, 104) after it (cut at the end). The five others ([0, 7) is not the predicted [0, 16))
    // gather their documents first and their E-step output with its sizes (two calls each). The
    // earlier exchange: every update makes those four calls.
    const std::int64_t calls = par.phase_times().collectives;
    EXPECT_EQ(calls, exchange == MpiLdaExchange::kLean ? 4 * 1 + 5 * 4 : 9 * 4);
  }
}

// The E-step's dealing (issue 23): largest cost first to the least loaded rank, the same on every
// rank; uneven documents end in near-equal loads where d mod P would not.
TEST(DataParallelLda, DealingByCostBalancesUnevenDocumentsDeterministically) {
  // One long document and ten short ones: d mod 2 gives loads 15 and 5; by cost 10 and 10.
  const std::vector<std::int64_t> costs{10, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  const std::vector<int> owner = mpi_deal_by_cost(costs, 2);
  ASSERT_EQ(owner.size(), costs.size());
  std::int64_t load[2] = {0, 0};
  for (std::size_t i = 0; i < costs.size(); ++i) load[owner[i]] += costs[i];
  EXPECT_EQ(load[0], 10);
  EXPECT_EQ(load[1], 10);
  EXPECT_EQ(owner[0], 0);                        // the largest first, to rank 0
  EXPECT_EQ(mpi_deal_by_cost(costs, 2), owner);  // deterministic
  // Equal costs: ranks take turns (fewest documents first), as d mod P would.
  EXPECT_EQ(mpi_deal_by_cost(std::vector<std::int64_t>{3, 3, 3, 3, 3}, 3),
            (std::vector<int>{0, 1, 2, 0, 1}));
  // Fewer documents than ranks, and empty documents (cost 0) spread by count.
  EXPECT_EQ(mpi_deal_by_cost(std::vector<std::int64_t>{5, 7}, 3), (std::vector<int>{1, 0}));
  EXPECT_EQ(mpi_deal_by_cost(std::vector<std::int64_t>{0, 0, 0, 0}, 2),
            (std::vector<int>{0, 1, 0, 1}));
  EXPECT_EQ(mpi_deal_by_cost(std::vector<std::int64_t>{4, 2}, 1), (std::vector<int>{0, 0}));
  // Random uneven costs: every load within the largest cost of the mean (LPT's bound).
  std::uint64_t x = 12345;
  std::vector<std::int64_t> many(257);
  for (auto& c : many) {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    c = static_cast<std::int64_t>((x >> 33) % 1000) * ((x >> 20) % 7 == 0 ? 20 : 1);
  }
  for (const int P : {2, 3, 5}) {
    const std::vector<int> o = mpi_deal_by_cost(many, P);
    std::vector<std::int64_t> l(static_cast<std::size_t>(P), 0);
    std::int64_t total = 0;
    std::int64_t largest = 0;
    for (std::size_t i = 0; i < many.size(); ++i) {
      l[static_cast<std::size_t>(o[i])] += many[i];
      total += many[i];
      largest = std::max(largest, many[i]);
    }
    for (const auto v : l) EXPECT_LE(std::abs(v * P - total), largest * P) << P << " ranks";
  }
}

TEST(DataParallelLda, TopicRowsAreContiguousBlocksCoveringEveryTopic) {
  EXPECT_EQ(mpi_topic_rows(7, 3, 0), std::make_pair(0, 2));
  EXPECT_EQ(mpi_topic_rows(7, 3, 1), std::make_pair(2, 4));
  EXPECT_EQ(mpi_topic_rows(7, 3, 2), std::make_pair(4, 7));
  EXPECT_EQ(mpi_topic_rows(2, 3, 0), std::make_pair(0, 0));  // fewer topics than ranks
  EXPECT_EQ(mpi_topic_rows(2, 3, 2), std::make_pair(1, 2));
  for (const int K : {1, 5, 100, 1000}) {
    for (const int P : {1, 2, 3, 16}) {
      int next = 0;
      for (int r = 0; r < P; ++r) {
        const auto [a, b] = mpi_topic_rows(K, P, r);
        EXPECT_EQ(a, next);
        EXPECT_LE(b - a, K / P + 1);
        next = b;
      }
      EXPECT_EQ(next, K);
    }
  }
}

}  // namespace
}  // namespace proprio::topics
