#pragma once
// Reading and writing text corpora in the three common bag-of-words formats (docs/formats/
// corpus.md): UCI bag-of-words (docword.txt + vocab.txt), Blei's LDA-C, and MatrixMarket
// coordinate files. Every reader checks every line; errors name the file and line.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "proprio/topics/corpus.hpp"

namespace proprio::topics {

enum class CorpusFormat { kUci, kLdac, kMatrixMarket };

/// "uci", "ldac" or "mm"; throws Error naming the accepted values otherwise.
CorpusFormat parse_corpus_format(std::string_view name);
std::string_view to_string(CorpusFormat format);

/// Caps on the sizes a corpus file declares, checked before anything is allocated: a model costs
/// K x W doubles, so a declared W is held to 1,000,000 words (the largest UCI corpus, PubMed, has
/// 141,043), and D to 10,000,000 documents (PubMed has 8.2 million). An LDA-C file without a
/// vocabulary takes W from its largest id, which is held to the same cap.
inline constexpr std::int64_t kMaxCorpusWords = 1'000'000;
inline constexpr std::int64_t kMaxCorpusDocuments = 10'000'000;

/// Reads a vocabulary file: one word per line, no blank or repeated words.
std::vector<std::string> read_vocabulary(const std::filesystem::path& path);

/// UCI bag-of-words: three header lines D, W, NNZ, then NNZ lines "docID wordID count" (1-based
/// ids, any order, each (doc, word) pair at most once). Documents without entries are empty
/// documents. `vocab` (W lines) may be an empty path: no vocabulary.
Corpus read_uci(const std::filesystem::path& docword, const std::filesystem::path& vocab);

/// LDA-C: one document per line, "N id:count id:count ..." with N distinct 0-based ids. The
/// number of words is the vocabulary's size when `vocab` is given, else the largest id + 1.
Corpus read_ldac(const std::filesystem::path& file, const std::filesystem::path& vocab);

/// MatrixMarket "coordinate integer general" (or real with integral values) matrix, one row per
/// document and one column per word, 1-based. `vocab` may be an empty path.
Corpus read_matrix_market(const std::filesystem::path& file, const std::filesystem::path& vocab);

/// Reads a corpus from a directory in the layout of docs/formats/corpus.md (uci: docword.txt and
/// vocab.txt, or the one docword.*.txt and vocab.*.txt; ldac: corpus.ldac or the one *.ldac or
/// *.dat file; mm: corpus.mm or the one *.mm file; vocab.txt optional for ldac and mm), or from
/// the corpus file itself (its vocabulary beside it).
Corpus read_corpus(const std::filesystem::path& dir_or_file, CorpusFormat format);

/// The files read_corpus reads for `dir_or_file`: the corpus file and its vocabulary (empty when
/// there is none). For checks that an output is not one of them.
struct CorpusFiles {
  std::filesystem::path file;
  std::filesystem::path vocabulary;
};
CorpusFiles find_corpus_files(const std::filesystem::path& dir_or_file, CorpusFormat format);

/// One rank's share of a corpus in a data-parallel job (issue 23): the documents d (0-based, in
/// file order) with d mod shards == shard, so that every mini-batch of the corpus is spread evenly
/// over the ranks. Reading parses and checks every line of the file as read_corpus does, as a
/// stream, and keeps only this shard's documents: no rank holds the whole corpus.
struct CorpusShard {
  Corpus documents;                  ///< this shard's documents, in corpus order
  std::int64_t total_documents = 0;  ///< D of the whole corpus
  std::int64_t total_tokens = 0;     ///< tokens of the whole corpus
  int shard = 0;
  int shards = 1;
  std::uint64_t bytes = 0;     ///< the corpus file's size
  std::uint64_t checksum = 0;  ///< FNV-1a (64 bits) of its lines: ranks compare it

  /// The corpus index of this shard's document `local`.
  [[nodiscard]] std::size_t global_index(std::size_t local) const {
    return local * static_cast<std::size_t>(shards) + static_cast<std::size_t>(shard);
  }
  /// The first of this shard's documents whose corpus index is >= `global`.
  [[nodiscard]] std::size_t first_local_at(std::size_t global) const {
    const auto s = static_cast<std::size_t>(shard);
    const auto n = static_cast<std::size_t>(shards);
    return global <= s ? 0 : (global - s + n - 1) / n;
  }
};

/// Reads shard `shard` of `shards` of a uci or ldac corpus (directory or file, as read_corpus);
/// throws Error as read_corpus does, and for mm (not readable as a stream of documents).
CorpusShard read_corpus_shard(const std::filesystem::path& dir_or_file, CorpusFormat format,
                              int shard, int shards);

/// Writes `corpus` into directory `dir` (created if missing) as docword.txt / corpus.ldac /
/// corpus.mm, plus vocab.txt when the corpus has a vocabulary; each file written atomically.
void write_corpus(const Corpus& corpus, const std::filesystem::path& dir, CorpusFormat format);

/// The corpus as text in the given format (without the vocabulary).
std::string format_corpus(const Corpus& corpus, CorpusFormat format);

}  // namespace proprio::topics
