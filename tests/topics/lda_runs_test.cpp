// topics/lda_runs.hpp: the library calls behind `proprio lda`, on synthetic corpora written to
// files: what they write, the records they return, and input that does not belong together.
#include "proprio/topics/lda_runs.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "../support/error_of.hpp"
#include "../support/named_corpus.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::topics {
namespace {
namespace fs = std::filesystem;

struct Files {
  test::TempDir dir{"proprio_lda_runs_"};
  fs::path train = dir.path() / "train";
  fs::path heldout = dir.path() / "heldout";
  Files() {
    SyntheticCorpusOptions o;
    o.num_topics = 3;
    o.num_words = 40;
    o.num_documents = 150;
    o.mean_length = 30;
    // The first 120 documents train, the last 30 are held out (the same topics).
    const Corpus all = test::named_synthetic_corpus(o);
    Corpus first(all.num_words(), all.vocabulary());
    Corpus last(all.num_words(), all.vocabulary());
    for (std::size_t d = 0; d < all.num_documents(); ++d) {
      const auto doc = all.document(d);
      (d < 120 ? first : last).add_document(doc.words, doc.counts);
    }
    write_corpus(first, train, CorpusFormat::kUci);
    write_corpus(last, heldout, CorpusFormat::kUci);
  }
};

LdaTrainingOptions training(const Files& f) {
  LdaTrainingOptions o;
  o.corpus = f.train;
  o.heldout = f.heldout;
  o.model = f.dir.path() / "m.lda";
  o.online.num_topics = 3;
  o.online.batch_size = 40;
  o.online.passes = 2;
  o.max_iterations = 5;
  return o;
}

TEST(LdaRuns, OnlineTrainingWritesTheModelAndRecordsWhatItUsed) {
  const Files f;
  const LdaTrainingOptions o = training(f);
  const LdaTrainingResult r = run_lda_training(o, {});
  const LdaModel saved = load_lda_model(o.model);
  EXPECT_EQ(saved.num_topics(), 3);
  EXPECT_EQ((saved.lambda - r.model.lambda).cwiseAbs().maxCoeff(), 0.0);
  const core::Json& d = r.document;
  EXPECT_EQ(d.at("format"), "proprio.lda.train");
  EXPECT_EQ(d.at("method"), "online");
  EXPECT_EQ(d.at("documents_in_corpus"), 120);
  EXPECT_EQ(d.at("documents"), 240);  // two passes
  // alpha and eta as used: 1/K.
  EXPECT_DOUBLE_EQ(d.at("options").at("alpha").get<double>(), 1.0 / 3);
  EXPECT_DOUBLE_EQ(d.at("options").at("eta").get<double>(), 1.0 / 3);
  EXPECT_EQ(d.at("options").at("topics"), 3);
  // The held-out trace: start and end, the last one reported.
  ASSERT_EQ(d.at("perplexity_trace").size(), 2U);
  EXPECT_EQ(d.at("heldout_perplexity"), d.at("perplexity_trace").back().at("perplexity"));
  // Learning: below the start's and below uniform over the 40 words.
  EXPECT_LT(d.at("heldout_perplexity").get<double>(),
            d.at("perplexity_trace").front().at("perplexity").get<double>());
  EXPECT_LT(d.at("heldout_perplexity").get<double>(), 40.0);
}

TEST(LdaRuns, BatchTrainingScoresTheHeldOutCorpusOnce) {
  const Files f;
  LdaTrainingOptions o = training(f);
  o.method = LdaMethod::kBatch;
  o.model.clear();  // nothing written
  const LdaTrainingResult r = run_lda_training(o, {});
  EXPECT_EQ(r.document.at("method"), "batch");
  EXPECT_EQ(r.document.at("iterations"), r.document.at("bound").size());
  EXPECT_TRUE(r.document.at("perplexity_trace").empty());
  EXPECT_GT(r.document.at("heldout_perplexity").get<double>(), 1.0);
  EXPECT_NE(r.brief().find("held-out perplexity"), std::string::npos) << r.brief();
  EXPECT_FALSE(fs::exists(f.dir.path() / "m.lda"));
}

TEST(LdaRuns, InferenceWritesARowPerDocument) {
  const Files f;
  const LdaTrainingOptions t = training(f);
  (void)run_lda_training(t, {});
  LdaInferenceOptions o;
  o.model = t.model;
  o.corpus = f.heldout;
  o.out = f.dir.path() / "theta.csv";
  const LdaInferenceResult r = run_lda_inference(o, {});
  EXPECT_EQ(r.summary.documents, 30);
  std::ifstream in(o.out);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "document,class,theta_0,theta_1,theta_2");
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_EQ(rows, 30);
  EXPECT_EQ(r.document.at("documents"), 30);
  // The record is the description: its keys are the described fields and the header's.
  std::vector<std::string> keys;
  for (const auto& [key, value] : r.document.items()) keys.push_back(key);
  std::vector<std::string> expected{"format", "format_version", "provenance"};
  for (const auto name : core::field_names<LdaInferenceResult>()) expected.emplace_back(name);
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(r.document.at("estep_capped"), r.summary.capped);
  EXPECT_EQ(r.document.at("out"), o.out.string());
}

TEST(LdaRuns, PerplexityOfAModelAndOfItsLambda) {
  const Files f;
  const LdaTrainingOptions t = training(f);
  (void)run_lda_training(t, {});
  LdaPerplexityOptions o;
  o.corpus = f.heldout;
  o.model = t.model;
  const LdaPerplexityResult by_model = run_lda_perplexity(o, {});
  // The same model through lda export's CSV and its priors gives the same perplexity.
  const LdaModel m = load_lda_model(t.model);
  write_lambda_csv(m, f.dir.path() / "lambda.csv", false);
  o.model.clear();
  o.lambda = f.dir.path() / "lambda.csv";
  o.alpha = m.alpha;
  o.eta = m.eta;
  const LdaPerplexityResult by_lambda = run_lda_perplexity(o, {});
  EXPECT_NEAR(by_lambda.perplexity.perplexity, by_model.perplexity.perplexity,
              1e-9 * by_model.perplexity.perplexity);
  EXPECT_NE(by_model.brief().find("perplexity "), std::string::npos);
}

TEST(LdaRuns, TopWordsNameTheModelsWords) {
  const Files f;
  const LdaTrainingOptions t = training(f);
  (void)run_lda_training(t, {});
  const LdaTopWords w = run_lda_top_words(t.model, 2, {});
  ASSERT_EQ(w.lines.size(), 3U);
  EXPECT_EQ(w.lines[0].rfind("topic 0: word", 0), 0U) << w.lines[0];
  EXPECT_EQ(w.document.at("topics").at(2).at("words").size(), 2U);
  // The Summary convention: brief() is the listing the CLI prints, message its first line.
  EXPECT_EQ(w.brief(), w.lines[0] + '\n' + w.lines[1] + '\n' + w.lines[2] + '\n');
  EXPECT_EQ(w.message, w.lines[0]);
  EXPECT_EQ(test::error_of([&] { (void)run_lda_top_words(t.model, 0, {}); }),
            "lda topics: --top must be >= 1");
}

TEST(LdaRuns, InputsThatDoNotBelongTogetherAreErrors) {
  const Files f;
  const LdaTrainingOptions t = training(f);
  (void)run_lda_training(t, {});
  // Another vocabulary size.
  SyntheticCorpusOptions s;
  s.num_words = 41;
  s.num_documents = 5;
  const fs::path other = f.dir.path() / "other";
  write_corpus(test::named_synthetic_corpus(s), other, CorpusFormat::kUci);
  LdaInferenceOptions o;
  o.model = t.model;
  o.corpus = other;
  o.out = f.dir.path() / "x.csv";
  EXPECT_EQ(test::error_of([&] { (void)run_lda_inference(o, {}); }),
            other.string() + ": has 41 words but the model has 40");
  EXPECT_FALSE(fs::exists(o.out));
  // The same size, another word.
  const LdaModel m = load_lda_model(t.model);
  Corpus renamed(40, [] {
    std::vector<std::string> v;
    v.reserve(40);
    for (int w = 0; w < 40; ++w) v.push_back(w == 7 ? "zebra" : "word" + std::to_string(w));
    return v;
  }());
  EXPECT_EQ(test::error_of([&] { check_corpus_matches_model(m, renamed, "c"); }),
            "c: word 8 is 'zebra' but the model's is 'word7'");
  // A held-out corpus over other words.
  LdaTrainingOptions bad = t;
  bad.heldout = other;
  EXPECT_EQ(test::error_of([&] { (void)run_lda_training(bad, {}); }),
            other.string() + ": has 41 words, the training corpus 40");
  // Options.
  bad = t;
  bad.online.kappa = 0.5;
  EXPECT_EQ(test::error_of([&] { (void)run_lda_training(bad, {}); }),
            "lda train: kappa must be in (0.5, 1] (it is 0.5)");
  LdaPerplexityOptions p;
  p.corpus = f.heldout;
  EXPECT_EQ(test::error_of([&] { (void)run_lda_perplexity(p, {}); }),
            "lda perplexity: give exactly one of --model and --lambda");
}

}  // namespace
}  // namespace proprio::topics
