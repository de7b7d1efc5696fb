// `mpirun -np N proprio lda train / vocab build` (issue 23) on this machine, over loopback: the
// model of 2 and 3 ranks is the one-process model byte for byte; bad input (ranks reading
// different corpora, more ranks than documents, a bad line) ends every rank with exit 2 and one
// line; a rank that dies ends the job within a bounded time and leaves no model; a build without
// MPI launched by mpirun says so on every rank and exits 2. Label `mpi`; not in the sanitizer
// build (Open MPI's own allocations would be reported as leaks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/named_corpus.hpp"
#include "../support/paths.hpp"
#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/corpus_io.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;

// mpirun as CI runs it: as root, more ranks than cores, a bounded time. Its session directory
// lies under this process's own temporary directory: ctest runs two test processes at once, and
// two mpiruns creating the shared /tmp/ompi.<host>.<uid> together can fail ("File exists").
std::string mpirun(int ranks) {
  static const test::TempDir kSessions("proprio_", "ompi_sessions");
  std::string s = "timeout 120 " PROPRIO_MPIEXEC
                  " --allow-run-as-root --oversubscribe --mca "
                  "orte_tmpdir_base ";
  s += kSessions.path().string();
  s += " -np ";
  s += std::to_string(ranks);
  s += " ";
  return s;
}

test::CliResult run(const std::string& command) {
  // run_cli prefixes the CLI; here the command line starts with mpirun, so run it through sh.
  std::string line = "--version >/dev/null; ";
  line += command;
  return test::run_cli(line);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto i = text.find(what); i != std::string::npos; i = text.find(what, i + 1)) ++n;
  return n;
}

// The integers that follow each occurrence of `key` in `text` (e.g. "\"collectives\": ").
std::vector<long long> numbers_after(const std::string& text, const std::string& key) {
  std::vector<long long> out;
  for (auto i = text.find(key); i != std::string::npos; i = text.find(key, i + 1)) {
    out.push_back(std::stoll(text.substr(i + key.size())));
  }
  return out;
}

class MpiLda : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    shared_dir = new test::TempDir("proprio_mpi_", "lda");
    topics::SyntheticCorpusOptions o;
    o.num_topics = 5;
    o.num_words = 150;
    o.num_documents = 301;  // not a multiple of 2 or 3: the last mini-batch is uneven
    o.mean_length = 40;
    o.seed = 7;
    topics::write_corpus(test::named_synthetic_corpus(o), path("c"), topics::CorpusFormat::kUci);
    o.seed = 8;
    topics::write_corpus(test::named_synthetic_corpus(o), path("other"),
                         topics::CorpusFormat::kUci);
    const auto r = test::run_cli("lda train --corpus " + path("c") + " " + kArgs +
                                 " --threads 2 --model " + path("one.lda"));
    ASSERT_EQ(r.code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete shared_dir;
    shared_dir = nullptr;
  }
  static std::string path(const std::string& name) { return (shared_dir->path() / name).string(); }
  static std::string cli() { return test::cli_path(); }
  static constexpr const char* kArgs = "-k 6 --batch 32 --passes 2 --seed 4";
  static test::TempDir* shared_dir;
};
test::TempDir* MpiLda::shared_dir = nullptr;

TEST_F(MpiLda, TwoAndThreeRanksWriteTheOneProcessModelByteForByte) {
  const std::string one = slurp(path("one.lda"));
  ASSERT_FALSE(one.empty());
  for (const int ranks : {2, 3}) {
    std::string name = "m";
    name += std::to_string(ranks);
    name += ".lda";
    const std::string model = path(name);
    std::string command = mpirun(ranks) + cli() + " lda train --corpus " + path("c") + " ";
    command += kArgs;
    command += " --threads 1 --model " + model;
    command += " --json " + model;
    command += ".json";
    const auto r = run(command);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(count_of(r.out, "mini-batch updates"), 1) << "rank 0 alone prints:\n" << r.out;
    EXPECT_TRUE(slurp(model) == one) << ranks << " ranks: another model";
    std::string ranks_field = "\"ranks\": ";
    ranks_field += std::to_string(ranks);
    EXPECT_NE(slurp(model + ".json").find(ranks_field), std::string::npos);
    // The record says how the ranks shared the work: the defaults.
    EXPECT_NE(slurp(model + ".json").find("\"mpi_exchange\": \"lean\""), std::string::npos);
    EXPECT_NE(slurp(model + ".json").find("\"mpi_design\": \"by-topic\""), std::string::npos);
    test::expect_schema_valid("lda_train.schema.json", model + ".json");
  }
}

// The update split by topic rows (each rank exp E[log beta], the statistics and the M-step of its
// rows, --mpi-design by-topic, the default) and the replicated one (--mpi-design replicated: every
// rank the whole M-step) give the one-process model byte for byte, also with K not a multiple of
// the ranks (7 topics; odd, so the topic sums' order is tested on every row) and fewer topics than
// ranks.
TEST_F(MpiLda, ByTopicAndReplicatedDesignsWriteTheOneProcessModel) {
  struct Case {
    int k;
    int ranks;
    const char* design;
  };
  for (const Case c : {Case{6, 2, "replicated"}, Case{6, 3, "replicated"}, Case{7, 2, "by-topic"},
                       Case{7, 3, "by-topic"}, Case{2, 3, "by-topic"}}) {
    std::string args = "--batch 32 --passes 2 --seed 4 -k ";
    args += std::to_string(c.k);
    std::string one = "one_k";
    one += std::to_string(c.k);
    one += ".lda";
    if (!fs::exists(path(one))) {
      const auto r = test::run_cli("lda train --corpus " + path("c") + " " + args +
                                   " --threads 2 --model " + path(one));
      ASSERT_EQ(r.code, 0) << r.err;
    }
    std::string name = "design_";
    name += c.design;
    name += std::to_string(c.k);
    name += "_";
    name += std::to_string(c.ranks);
    name += ".lda";
    // With a held-out corpus scored every 3 updates by rank 0: every rank gathers the rows.
    std::string command = mpirun(c.ranks) + cli() + " lda train --corpus " + path("c") + " " +
                          args + " --heldout " + path("other") +
                          " --evaluate-every 3 --threads 1 --phase-times --mpi-design ";
    command += c.design;
    command += " --model " + path(name);
    const auto r = run(command);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(slurp(path(name)) == slurp(path(one)))
        << c.design << ", K " << c.k << ", " << c.ranks << " ranks: another model";
    // Every rank reports its phases once (its E-step and its wait beside them).
    EXPECT_EQ(count_of(r.err, "\"phase_times\""), c.ranks) << r.err;
    EXPECT_EQ(count_of(r.err, "\"wait_wall\""), c.ranks) << r.err;
    // The lean exchange: each update one allgather (one MPI call, sizes known) of the E-step
    // output with the next batch's documents, by topic one more of the beta rows; the first
    // update gathers its documents (sizes, then bytes) and its E-step output (the same) first.
    const auto updates = numbers_after(r.err, "\"updates\":");
    const auto calls = numbers_after(r.err, "\"collectives\":");
    ASSERT_EQ(calls.size(), static_cast<std::size_t>(c.ranks)) << r.err;
    for (std::size_t q = 0; q < calls.size(); ++q) {
      const long long per = std::strcmp(c.design, "by-topic") == 0 ? 2 : 1;
      EXPECT_EQ(calls[q], per * updates[q] + 3) << r.err;
    }
  }
}

// The E-step dealt by cost (the default) on a corpus of very uneven documents (every seventh 40
// times longer, some empty): the one-process model byte for byte on 2 and 3 ranks, with fewer
// topics than ranks, and with the old dealing and exchange (d mod P and three allgathers a batch:
// --mpi-dealing modulo --mpi-exchange three).
TEST_F(MpiLda, UnevenDocumentsDealtByCostGiveTheOneProcessModel) {
  std::vector<std::string> vocab;
  for (int w = 0; w < 120; ++w) {
    std::string word = "u";
    word += std::to_string(w);
    vocab.push_back(word);
  }
  topics::Corpus uneven(120, vocab);
  for (int d = 0; d < 157; ++d) {
    const int n = d % 7 == 3 ? 80 : (d % 11 == 5 ? 0 : 2 + d % 3);
    std::vector<std::int32_t> words;
    std::vector<std::int32_t> counts;
    for (int i = 0; i < n; ++i) {
      words.push_back((d * 13 + i * 7) % 120);
      counts.push_back(1 + (d + i) % 4);
    }
    std::sort(words.begin(), words.end());
    words.erase(std::unique(words.begin(), words.end()), words.end());
    counts.resize(words.size());
    uneven.add_document(words, counts);
  }
  topics::write_corpus(uneven, path("uneven"), topics::CorpusFormat::kUci);
  struct Case {
    int k;
    int ranks;
    bool balance;
  };
  for (const Case c : {Case{6, 2, true}, Case{6, 3, true}, Case{2, 3, true}, Case{6, 2, false}}) {
    std::string args = "--batch 24 --passes 2 --seed 5 -k ";
    args += std::to_string(c.k);
    std::string one = "uneven_one_k";
    one += std::to_string(c.k);
    one += ".lda";
    if (!fs::exists(path(one))) {
      const auto r = test::run_cli("lda train --corpus " + path("uneven") + " " + args +
                                   " --threads 1 --model " + path(one));
      ASSERT_EQ(r.code, 0) << r.err;
    }
    std::string name = "uneven_k";
    name += std::to_string(c.k);
    name += "_";
    name += std::to_string(c.ranks);
    name += c.balance ? "_balanced.lda" : "_mod.lda";
    std::string command = mpirun(c.ranks) + cli() + " lda train --corpus " + path("uneven") + " " +
                          args + " --threads 1 --phase-times --model " + path(name);
    if (!c.balance) command += " --mpi-dealing modulo --mpi-exchange three";
    const auto r = run(command);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(slurp(path(name)) == slurp(path(one)))
        << "K " << c.k << ", " << c.ranks << " ranks, balance " << c.balance << ": another model";
    // The exchange asked for ran: the earlier one makes 6 MPI calls an update by topic (3
    // allgathers of unknown sizes), the lean one 2 (and 3 more for the first update).
    const auto updates = numbers_after(r.err, "\"updates\":");
    const auto calls = numbers_after(r.err, "\"collectives\":");
    ASSERT_EQ(calls.size(), static_cast<std::size_t>(c.ranks)) << r.err;
    for (std::size_t q = 0; q < calls.size(); ++q) {
      EXPECT_EQ(calls[q], c.balance ? 2 * updates[q] + 3 : 6 * updates[q]) << r.err;
    }
  }
}

TEST_F(MpiLda, RanksThatReadDifferentCorporaAllExit2WithOneLine) {
  std::string train = " lda train ";
  train += kArgs;
  train += " --model ";
  train += path("x.lda");
  const auto r = run(mpirun(1) + cli() + train + " --corpus " + path("c") + " : -np 2 " + cli() +
                     train + " --corpus " + path("other"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_of(r.err, "proprio: "), 1) << r.err;
  EXPECT_NE(r.err.find("read different corpora"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("x.lda")));
}

// The same corpus but other options on one rank (a library caller could do it; mpirun's MPMD
// form lets the CLI do it too): another exchange, design or kappa would desynchronise the
// collectives or the model, so every rank stops with one line. Other thread counts are allowed
// (no bit changes), and the job then writes the one-process model.
TEST_F(MpiLda, RanksGivenDifferentOptionsAllExit2WithOneLine) {
  std::string train = " lda train --corpus ";
  train += path("c");
  train += " ";
  train += kArgs;
  train += " --model ";
  train += path("opt.lda");
  for (const std::string other :
       {" --mpi-exchange three", " --kappa 0.8", " --mpi-design replicated"}) {
    std::string line = mpirun(2) + cli() + train;
    line += " : -np 1 ";
    line += cli() + train;
    line += other;
    const auto r = run(line);
    EXPECT_EQ(r.code, 2) << other << "\n" << r.err;
    EXPECT_EQ(count_of(r.err, "proprio: "), 1) << r.err;
    EXPECT_NE(r.err.find("3 MPI ranks were given different training options"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("opt.lda")));
  }
  const auto r =
      run(mpirun(1) + cli() + train + " --threads 2 : -np 1 " + cli() + train + " --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(path("opt.lda")), slurp(path("one.lda")));
}

TEST_F(MpiLda, MoreRanksThanDocumentsAndBadLinesExit2WithOneLine) {
  const test::TempDir d("proprio_mpi_", "tiny");
  {
    std::ofstream(d.path() / "docword.txt") << "2\n3\n2\n1 1 1\n2 2 1\n";
    std::ofstream(d.path() / "vocab.txt") << "a\nb\nc\n";
  }
  auto r = run(mpirun(3) + cli() + " lda train -k 2 --corpus " + d.path().string() + " --model " +
               path("y.lda"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_of(r.err, "proprio: "), 1) << r.err;
  EXPECT_NE(r.err.find("2 documents for 3 MPI ranks"), std::string::npos) << r.err;
  // A bad line in the document of rank 1: every rank reads it, every rank stops.
  std::ofstream(d.path() / "docword.txt") << "2\n3\n2\n1 1 1\n2 9 1\n";
  r = run(mpirun(2) + cli() + " lda train -k 2 --corpus " + d.path().string() + " --model " +
          path("y.lda"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_of(r.err, "proprio: "), 1) << r.err;
  EXPECT_NE(r.err.find("docword.txt:5: wordID 9 outside [1, 3]"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("y.lda")));
}

TEST_F(MpiLda, ARankThatDiesEndsTheJobAndLeavesNoModel) {
  const std::string model = path("dead.lda");
  std::string command = "PROPRIO_MPI_TEST_FAIL=1:5 ";
  command += mpirun(3) + cli() + " lda train --corpus " + path("c") + " " + kArgs + " --model ";
  command += model;
  const auto r = run(command);
  EXPECT_NE(r.code, 0) << r.err;
  EXPECT_NE(r.code, 124) << "timed out: the job hung";
  EXPECT_NE(r.err.find("rank 1: aborting before update 5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exited on signal"), std::string::npos) << "mpirun names the dead rank\n"
                                                               << r.err;
  EXPECT_FALSE(fs::exists(model));
  for (const auto& e : fs::directory_iterator(shared_dir->path())) {
    EXPECT_EQ(e.path().string().find("dead.lda"), std::string::npos) << e.path();
  }
}

// k-means vocabularies: 2 and 3 ranks give the one-process words (the files differ only in their
// provenance's time), sampled (--per-image) and whole, and the same record.
TEST(MpiVocab, TwoAndThreeRanksBuildTheOneProcessVocabulary) {
  const test::TempDir dir("proprio_mpi_", "vocab");
  const fs::path samples = PROPRIO_OPENCV_SAMPLES;
  const std::vector<std::pair<std::string, std::vector<std::string>>> set{
      {"fruit", {"apple.jpg", "orange.jpg", "fruits.jpg"}},
      {"scene", {"box_in_scene.png", "graf1.png"}}};
  for (const auto& [cls, files] : set) {
    fs::create_directories(dir.path() / "images" / cls);
    for (const auto& f : files) fs::copy_file(samples / f, dir.path() / "images" / cls / f);
  }
  const std::string images = (dir.path() / "images").string();
  for (const std::string per_image : {"60", "0"}) {
    std::string args = " vocab build --no-progress --words 24 --seed 3 --per-image ";
    args += per_image;
    args += " --images ";
    args += images;
    const auto out = [&](const std::string& name) { return (dir.path() / name).string(); };
    const auto one = test::run_cli(args.substr(1) + " --threads 2 --out " + out("one.voc") +
                                   " --json " + out("one.json"));
    ASSERT_EQ(one.code, 0) << one.err;
    const features::Vocabulary v1 = features::read_vocabulary(out("one.voc"));
    const core::Json j1 = core::read_json(out("one.json"));
    for (const int ranks : {2, 3}) {
      if (per_image == "0" && ranks == 2) continue;  // time: whole images once, on 3 ranks
      std::string name = "v";
      name += std::to_string(ranks);
      const auto r = run(mpirun(ranks) + test::cli_path() + args + " --threads 1 --out " +
                         out(name + ".voc") + " --json " + out(name + ".json"));
      ASSERT_EQ(r.code, 0) << r.err;
      const features::Vocabulary v = features::read_vocabulary(out(name + ".voc"));
      ASSERT_EQ(v.size(), v1.size());
      ASSERT_EQ(v.dimension(), v1.dimension());
      EXPECT_EQ(std::memcmp(v.words().ptr<float>(), v1.words().ptr<float>(),
                            v1.words().total() * sizeof(float)),
                0)
          << ranks << " ranks, --per-image " << per_image << ": other words";
      const core::Json j = core::read_json(out(name + ".json"));
      EXPECT_EQ(j["cost"], j1["cost"]);
      EXPECT_EQ(j["iterations"], j1["iterations"]);
      EXPECT_EQ(j["descriptors"], j1["descriptors"]);
      EXPECT_EQ(j["ranks"], ranks);
      test::expect_schema_valid("vocab_build.schema.json", out(name + ".json"));
    }
    if (per_image == "0") continue;
    // One rank given other options (mpirun's MPMD form): every rank stops with one line, nothing
    // written.
    for (const std::string other :
         {" --min-contrast 3", " --max-iterations 7", " --seeding-trials 2"}) {
      std::string line = mpirun(1) + test::cli_path() + args;
      line += " --out " + out("bad.voc");
      line += " : -np 1 " + test::cli_path() + args;
      line += other;
      line += " --out " + out("bad.voc");
      const auto r = run(line);
      EXPECT_EQ(r.code, 2) << other << "\n" << r.err;
      EXPECT_EQ(count_of(r.err, "proprio: "), 1) << r.err;
      EXPECT_NE(r.err.find("2 MPI ranks were given different options"), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(out("bad.voc")));
    }
  }
}

TEST(MpiWithoutMpi, ABuildWithoutMpiUnderMpirunExits2OnEveryRank) {
  const fs::path stub =
      fs::path(test::cli_path()).parent_path().parent_path() / "tests" / "app" / "mpi_stub_world";
  ASSERT_TRUE(fs::exists(stub)) << stub;
  const auto r = run(mpirun(2) + stub.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_of(r.err, "built without MPI"), 2) << r.err;
  EXPECT_EQ(count_of(r.out, "local world"), 0);
}

}  // namespace
}  // namespace proprio
