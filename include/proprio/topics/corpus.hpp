#pragma once
// A corpus of bag-of-words documents (thesis B.1): each document is the set of its distinct word
// ids with their counts. Words are text words or visual words alike; the vocabulary (one string
// per word id) is optional.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace proprio::topics {

/// One document: distinct word ids in increasing order, each with its count (> 0). An empty
/// document (no words) is allowed.
struct DocumentView {
  std::span<const std::int32_t> words;
  std::span<const std::int32_t> counts;

  [[nodiscard]] std::size_t size() const { return words.size(); }
  [[nodiscard]] bool empty() const { return words.empty(); }
  /// Number of tokens: the sum of the counts.
  [[nodiscard]] std::int64_t tokens() const;
};

/// Documents over a vocabulary of `num_words` words, stored contiguously (compressed rows).
class Corpus {
 public:
  Corpus() = default;
  /// An empty corpus over `num_words` words; `vocabulary` is empty or has `num_words` entries.
  explicit Corpus(std::int32_t num_words, std::vector<std::string> vocabulary = {});

  /// Appends a document given as (word id, count) pairs in any order; repeated ids are summed.
  /// Throws Error when an id is outside [0, num_words) or a count is <= 0 (the message names
  /// the document's index).
  void add_document(std::span<const std::int32_t> words, std::span<const std::int32_t> counts);
  /// Appends a document given as a list of tokens (word ids, repeats allowed).
  void add_tokens(std::span<const std::int32_t> tokens);

  [[nodiscard]] std::size_t num_documents() const { return offsets_.size() - 1; }
  [[nodiscard]] std::int32_t num_words() const { return num_words_; }
  /// Total number of tokens (sum of all counts).
  [[nodiscard]] std::int64_t num_tokens() const { return num_tokens_; }
  /// Number of (document, distinct word) entries.
  [[nodiscard]] std::size_t num_entries() const { return words_.size(); }
  [[nodiscard]] const std::vector<std::string>& vocabulary() const { return vocabulary_; }

  [[nodiscard]] DocumentView document(std::size_t d) const;

  /// The documents with the given indices, in that order, over the same vocabulary.
  [[nodiscard]] Corpus subset(std::span<const std::size_t> indices) const;

  bool operator==(const Corpus&) const = default;

 private:
  std::int32_t num_words_ = 0;
  std::vector<std::string> vocabulary_;
  std::vector<std::size_t> offsets_{0};
  std::vector<std::int32_t> words_;
  std::vector<std::int32_t> counts_;
  std::int64_t num_tokens_ = 0;
};

/// A corpus split into a training part and a held-out part.
struct CorpusSplit {
  Corpus train;
  Corpus heldout;
};

/// Holds out round(fraction * D) documents chosen at random (seeded), keeping the order of the
/// rest. Used for held-out perplexity.
CorpusSplit hold_out(const Corpus& corpus, double fraction, std::uint64_t seed);

/// The largest weight of a word (weighted_by; the bound of LdaModel::word_weights too).
inline constexpr std::int32_t kMaxWordWeight = 1000;

/// The documents of `corpus` with each occurrence of word w counted weights[w] times, the
/// documents, their order and the vocabulary's names kept: a topic model's documents in which
/// some words weigh more (proprio's colour words: LdaModel::word_weights). Counts, not repeated
/// tokens, so the inference's work grows little. Throws Error when there are not num_words
/// weights or one is outside [1, kMaxWordWeight].
Corpus weighted_by(const Corpus& corpus, std::span<const std::int32_t> weights);

/// `num_words` weights: 1 below `first`, `weight` from `first` on (the colour words, numbered
/// after the vocabulary's: `first` = the vocabulary's size). Throws Error when `first` is outside
/// [0, num_words] or `weight` outside [1, kMaxWordWeight].
std::vector<std::int32_t> weights_from(int num_words, int first, int weight);

/// weighted_by(corpus, weights_from(corpus.num_words(), first, weight)); weight 1 gives
/// `corpus` as it is.
Corpus weighted_from(const Corpus& corpus, int first, int weight);

}  // namespace proprio::topics
