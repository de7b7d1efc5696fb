// Corpora: round trips through the three formats, and bad input named by file and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "proprio/core/error.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/corpus_io.hpp"

namespace proprio::topics {
namespace {
namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    static int n = 0;
    path_ = fs::temp_directory_path() /
            ("proprio_corpus_test_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  [[nodiscard]] const fs::path& path() const { return path_; }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name, std::ios::binary) << text;
    return path_ / name;
  }

 private:
  fs::path path_;
};

Corpus sample() {
  Corpus c(5, {"apple", "banana", "cherry", "date", "elder"});
  c.add_document(std::vector<std::int32_t>{3, 0, 3}, std::vector<std::int32_t>{2, 1, 1});
  c.add_document({}, {});  // an empty document
  c.add_tokens(std::vector<std::int32_t>{4, 4, 1});
  return c;
}

// Expects `f` to throw Error whose message contains every fragment.
template <typename F>
void expect_error(F f, std::initializer_list<std::string> fragments) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    for (const auto& frag : fragments) EXPECT_NE(m.find(frag), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line: " << m;
  }
}

TEST(Corpus, AddsSortsAndSumsRepeatedWords) {
  const Corpus c = sample();
  ASSERT_EQ(c.num_documents(), 3u);
  const auto d0 = c.document(0);
  ASSERT_EQ(d0.size(), 2u);
  EXPECT_EQ(d0.words[0], 0);
  EXPECT_EQ(d0.words[1], 3);
  EXPECT_EQ(d0.counts[1], 3);
  EXPECT_TRUE(c.document(1).empty());
  EXPECT_EQ(c.document(2).tokens(), 3);
  EXPECT_EQ(c.num_tokens(), 7);
  EXPECT_EQ(c.num_entries(), 4u);
}

TEST(Corpus, RejectsBadIdsAndCounts) {
  Corpus c(3);
  expect_error([&] { c.add_tokens(std::vector<std::int32_t>{3}); }, {"document 0", "word id 3"});
  expect_error([&] { c.add_document(std::vector<std::int32_t>{1}, std::vector<std::int32_t>{0}); },
               {"count 0", "not positive"});
  EXPECT_THROW(Corpus(2, {"a"}), Error);
}

TEST(Corpus, SubsetAndHoldOut) {
  const Corpus c = sample();
  const std::vector<std::size_t> idx{2, 0};
  const Corpus s = c.subset(idx);
  EXPECT_EQ(s.num_documents(), 2u);
  EXPECT_EQ(s.document(0).tokens(), 3);
  EXPECT_EQ(s.num_tokens(), 7);
  Corpus big(10);
  for (int d = 0; d < 100; ++d) big.add_tokens(std::vector<std::int32_t>{d % 10});
  const CorpusSplit sp = hold_out(big, 0.1, 4);
  EXPECT_EQ(sp.heldout.num_documents(), 10u);
  EXPECT_EQ(sp.train.num_documents(), 90u);
  EXPECT_TRUE(hold_out(big, 0.1, 4).heldout == sp.heldout);
  EXPECT_FALSE(hold_out(big, 0.1, 5).heldout == sp.heldout);
}

TEST(CorpusIo, RoundTripsEveryFormat) {
  const Corpus c = sample();
  for (const auto f : {CorpusFormat::kUci, CorpusFormat::kLdac, CorpusFormat::kMatrixMarket}) {
    TempDir dir;
    write_corpus(c, dir.path(), f);
    const Corpus back = read_corpus(dir.path(), f);
    EXPECT_TRUE(back == c) << to_string(f);
    EXPECT_EQ(back.vocabulary(), c.vocabulary()) << to_string(f);
    EXPECT_EQ(parse_corpus_format(to_string(f)), f);
  }
  EXPECT_THROW(parse_corpus_format("csv"), Error);
}

TEST(CorpusIo, ReadsUciByItsOwnNamesAndFromTheFile) {
  TempDir dir;
  dir.write("docword.kos.txt", "2\n3\n3\n1 1 4\n2 3 1\n1 2 2\n");
  dir.write("vocab.kos.txt", "a\nb\nc\n");
  const Corpus c = read_corpus(dir.path(), CorpusFormat::kUci);
  ASSERT_EQ(c.num_documents(), 2u);
  EXPECT_EQ(c.document(0).tokens(), 6);
  EXPECT_EQ(c.vocabulary()[2], "c");
  EXPECT_TRUE(read_corpus(dir.path() / "docword.kos.txt", CorpusFormat::kUci) == c);
}

TEST(CorpusIo, UciErrorsNameTheFileAndLine) {
  TempDir dir;
  const auto vocab = dir.write("vocab.txt", "a\nb\nc\n");
  auto bad = [&](const std::string& text, std::initializer_list<std::string> frags) {
    const auto f = dir.write("docword.txt", text);
    expect_error([&] { read_uci(f, vocab); }, frags);
  };
  bad("2\n3\n2\n1 1 1\n1 x 2\n", {"docword.txt:5:", "wordID is not an integer"});
  bad("2\n3\n2\n1 1 1\n1 2\n", {"docword.txt:5:", "expected 'docID wordID count'"});
  bad("2\n3\n2\n1 1 1\n1 4 2\n", {"docword.txt:5:", "wordID 4 outside [1, 3]"});
  bad("2\n3\n2\n1 1 1\n3 1 2\n", {"docword.txt:5:", "docID 3 outside [1, 2]"});
  bad("2\n3\n2\n1 1 1\n1 2 0\n", {"docword.txt:5:", "count 0 is not positive"});
  bad("2\n3\n2\n1 1 1\n1 2 -3\n", {"docword.txt:5:", "count -3"});
  bad("2\n3\n2\n1 1 1\n1 1 2\n", {"docword.txt:5:", "repeats the entry of line 4"});
  bad("2\n3\n3\n1 1 1\n1 2 2\n", {"docword.txt", "truncated", "NNZ is 3", "has 2"});
  bad("2\n3\n1\n1 1 1\n1 2 2\n", {"docword.txt:5:", "more entries than the header's NNZ = 1"});
  bad("2\n3\n", {"docword.txt", "truncated"});
  bad("2\n4\n1\n1 1 1\n", {"vocab.txt", "has 3 words", "W = 4"});
  bad("2\n3 3\n1\n", {"docword.txt:2:", "expected one integer"});
  bad("-2\n3\n1\n", {"docword.txt:1:", "negative"});
  bad("1000000\n1000000\n999999999999999999\n", {"exceeds D x W"});
  bad("", {"truncated"});
}

TEST(CorpusIo, EmptyDocumentsInUciAreKept) {
  TempDir dir;
  const auto f = dir.write("docword.txt", "4\n2\n2\n1 1 1\n4 2 3\n");
  const Corpus c = read_uci(f, {});
  ASSERT_EQ(c.num_documents(), 4u);
  EXPECT_TRUE(c.document(1).empty());
  EXPECT_TRUE(c.document(2).empty());
  EXPECT_EQ(c.document(3).tokens(), 3);
  EXPECT_TRUE(c.vocabulary().empty());
}

TEST(CorpusIo, VocabularyErrors) {
  TempDir dir;
  expect_error([&] { read_vocabulary(dir.write("v1.txt", "a\n\nb\n")); }, {"v1.txt:2:", "blank"});
  expect_error([&] { read_vocabulary(dir.write("v2.txt", "a\nb\na\n")); },
               {"v2.txt:3:", "'a' appears twice"});
  expect_error([&] { read_vocabulary(dir.write("v3.txt", "")); }, {"v3.txt", "empty"});
  expect_error([&] { read_vocabulary(dir.path() / "missing.txt"); }, {"missing.txt"});
}

TEST(CorpusIo, LdacErrorsNameTheFileAndLine) {
  TempDir dir;
  auto bad = [&](const std::string& text, std::initializer_list<std::string> frags,
                 const fs::path& vocab = {}) {
    const auto f = dir.write("c.ldac", text);
    expect_error([&] { read_ldac(f, vocab); }, frags);
  };
  bad("2 0:1 1:2\n3 0:1 2:2\n", {"c.ldac:2:", "N = 3", "2 id:count pairs"});
  bad("1 0:1\n\n1 1:1\n", {"c.ldac:2:", "blank line"});
  bad("1 0-1\n", {"c.ldac:1:", "expected id:count"});
  bad("1 0:0\n", {"c.ldac:1:", "count 0"});
  bad("2 1:1 1:2\n", {"c.ldac:1:", "repeats"});
  bad("1 -1:1\n", {"c.ldac:1:", "word id -1"});
  bad("1 5:1\n", {"c.ldac:1:", "word id 5 outside [0, 2)"}, dir.write("vocab.txt", "a\nb\n"));
  bad("", {"no documents"});
  // "0" is an empty document; W is the largest id + 1 without a vocabulary.
  const Corpus c = read_ldac(dir.write("ok.ldac", "1 4:2\n0\n"), {});
  EXPECT_EQ(c.num_words(), 5);
  EXPECT_EQ(c.num_documents(), 2u);
  EXPECT_TRUE(c.document(1).empty());
}

TEST(CorpusIo, MatrixMarketReadsRealAndPatternAndNamesBadLines) {
  TempDir dir;
  const Corpus r = read_matrix_market(
      dir.write("r.mm",
                "%%MatrixMarket matrix coordinate real general\n% c\n2 3 2\n1 3 2.0\n2 1 1\n"),
      {});
  EXPECT_EQ(r.document(0).words[0], 2);
  EXPECT_EQ(r.document(0).counts[0], 2);
  const Corpus p = read_matrix_market(
      dir.write("p.mm", "%%MatrixMarket matrix coordinate pattern general\n1 2 1\n1 2\n"), {});
  EXPECT_EQ(p.num_tokens(), 1);
  auto bad = [&](const std::string& text, std::initializer_list<std::string> frags) {
    const auto f = dir.write("b.mm", text);
    expect_error([&] { read_matrix_market(f, {}); }, frags);
  };
  const std::string head = "%%MatrixMarket matrix coordinate integer general\n";
  bad("%%MatrixMarket matrix array real general\n", {"b.mm:1:"});
  bad("%%MatrixMarket matrix coordinate integer symmetric\n", {"b.mm:1:", "symmetry"});
  bad(head + "2 3 2\n1 1 1\n", {"b.mm", "truncated", "promises 2"});
  bad(head + "2 3 1\n1 4 1\n", {"b.mm:3:", "word 4 outside [1, 3]"});
  bad(head + "2 3 1\n1 1 0\n", {"b.mm:3:", "count 0"});
  bad("%%MatrixMarket matrix coordinate real general\n2 3 1\n1 1 1.5\n",
      {"b.mm:3:", "not a whole number"});
  bad(head + "2 3 1\n1 1 1 1\n", {"b.mm:3:", "expected 'document word count'"});
  bad(head, {"truncated: no size line"});
}

// Issue 16: a 12-byte LDA-C corpus naming word id 9,999,999 trained an 800 MB model; a
// MatrixMarket size line with W = 10^9 ended in "internal error: std::bad_alloc".
TEST(CorpusIo, DeclaredSizesAreHeldToTheCaps) {
  TempDir dir;
  expect_error([&] { read_ldac(dir.write("big.ldac", "1 9999999:1\n"), {}); },
               {"big.ldac:1:", "word id 9999999 outside [0, 1000000)"});
  EXPECT_EQ(read_ldac(dir.write("ok.ldac", "1 999999:1\n"), {}).num_words(), kMaxCorpusWords);
  const std::string head = "%%MatrixMarket matrix coordinate integer general\n";
  expect_error([&] { read_matrix_market(dir.write("w.mm", head + "1 1000000000 1\n1 1 1\n"), {}); },
               {"w.mm:2:", "W = 1000000000 words is more than the 1000000"});
  expect_error([&] { read_matrix_market(dir.write("d.mm", head + "2000000000 5 0\n"), {}); },
               {"d.mm:2:", "D = 2000000000 documents is more than the 10000000"});
  expect_error([&] { read_uci(dir.write("docword.txt", "3\n2000000\n1\n1 1 1\n"), {}); },
               {"docword.txt:3:", "W = 2000000 words"});
}

TEST(CorpusIo, DirectoryLookupErrors) {
  TempDir dir;
  expect_error([&] { read_corpus(dir.path() / "nope", CorpusFormat::kUci); },
               {"no such file or directory"});
  expect_error([&] { read_corpus(dir.path(), CorpusFormat::kUci); }, {"no docword.txt"});
  dir.write("a.ldac", "0\n");
  dir.write("b.ldac", "0\n");
  expect_error([&] { read_corpus(dir.path(), CorpusFormat::kLdac); }, {"several candidates"});
  dir.write("docword.txt", "1\n1\n0\n");
  expect_error([&] { read_corpus(dir.path(), CorpusFormat::kUci); }, {"no vocab.txt"});
}

}  // namespace
}  // namespace proprio::topics
