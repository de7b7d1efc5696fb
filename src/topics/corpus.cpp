#include "proprio/topics/corpus.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/core/text.hpp"

namespace proprio::topics {

std::int64_t DocumentView::tokens() const {
  std::int64_t n = 0;
  for (const auto c : counts) n += c;
  return n;
}

Corpus::Corpus(std::int32_t num_words, std::vector<std::string> vocabulary)
    : num_words_(num_words), vocabulary_(std::move(vocabulary)) {
  assert(num_words >= 0);
  if (!vocabulary_.empty() && static_cast<std::int64_t>(vocabulary_.size()) != num_words) {
    throw Error("corpus: a vocabulary of " + std::to_string(vocabulary_.size()) + " words for " +
                std::to_string(num_words) + " word ids");
  }
}

void Corpus::add_document(std::span<const std::int32_t> words,
                          std::span<const std::int32_t> counts) {
  assert(words.size() == counts.size());
  const std::size_t d = num_documents();
  std::vector<std::pair<std::int32_t, std::int32_t>> entries(words.size());
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (words[i] < 0 || words[i] >= num_words_) {
      throw Error("document " + std::to_string(d) + ": word id " + std::to_string(words[i]) +
                  " outside [0, " + std::to_string(num_words_) + ")");
    }
    if (counts[i] <= 0) {
      throw Error("document " + std::to_string(d) + ": count " + std::to_string(counts[i]) +
                  " of word " + std::to_string(words[i]) + " is not positive");
    }
    entries[i] = {words[i], counts[i]};
  }
  const bool sorted = std::is_sorted(entries.begin(), entries.end());
  if (!sorted) std::sort(entries.begin(), entries.end());
  std::int64_t tokens = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    tokens += entries[i].second;
    if (!words_.empty() && words_.size() > offsets_.back() && words_.back() == entries[i].first) {
      const std::int64_t sum = static_cast<std::int64_t>(counts_.back()) + entries[i].second;
      if (sum > INT32_MAX) {
        throw Error("document " + std::to_string(d) + ": count of word " +
                    std::to_string(entries[i].first) + " overflows");
      }
      counts_.back() = static_cast<std::int32_t>(sum);
    } else {
      words_.push_back(entries[i].first);
      counts_.push_back(entries[i].second);
    }
  }
  offsets_.push_back(words_.size());
  num_tokens_ += tokens;
}

void Corpus::add_tokens(std::span<const std::int32_t> tokens) {
  std::vector<std::int32_t> ones(tokens.size(), 1);
  add_document(tokens, ones);
}

DocumentView Corpus::document(std::size_t d) const {
  assert(d < num_documents());
  const std::size_t b = offsets_[d];
  const std::size_t n = offsets_[d + 1] - b;
  return {std::span<const std::int32_t>(words_.data() + b, n),
          std::span<const std::int32_t>(counts_.data() + b, n)};
}

Corpus Corpus::subset(std::span<const std::size_t> indices) const {
  Corpus out(num_words_, vocabulary_);
  std::size_t entries = 0;
  for (const auto d : indices) entries += document(d).size();
  out.words_.reserve(entries);
  out.counts_.reserve(entries);
  out.offsets_.reserve(indices.size() + 1);
  for (const auto d : indices) {
    const auto doc = document(d);
    out.words_.insert(out.words_.end(), doc.words.begin(), doc.words.end());
    out.counts_.insert(out.counts_.end(), doc.counts.begin(), doc.counts.end());
    out.offsets_.push_back(out.words_.size());
    out.num_tokens_ += doc.tokens();
  }
  return out;
}

CorpusSplit hold_out(const Corpus& corpus, double fraction, std::uint64_t seed) {
  if (!(fraction >= 0.0 && fraction <= 1.0)) {
    throw Error("hold_out: fraction " + std::to_string(fraction) + " outside [0, 1]");
  }
  const std::size_t n = corpus.num_documents();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  core::Rng rng(seed);
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.index(i)]);
  const auto held = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(n)));
  std::vector<std::size_t> heldout(order.begin(), order.begin() + static_cast<long>(held));
  std::vector<std::size_t> train(order.begin() + static_cast<long>(held), order.end());
  std::sort(heldout.begin(), heldout.end());
  std::sort(train.begin(), train.end());
  return {corpus.subset(train), corpus.subset(heldout)};
}

Corpus weighted_by(const Corpus& corpus, std::span<const std::int32_t> weights) {
  if (std::ssize(weights) != corpus.num_words()) {
    throw Error(core::cat({"weighted_by: ", std::to_string(weights.size()), " weights for ",
                           std::to_string(corpus.num_words()), " words"}));
  }
  for (const std::int32_t w : weights) {
    if (w < 1 || w > kMaxWordWeight) {
      throw Error(core::cat({"weighted_by: a weight of ", std::to_string(w), ", not in [1, ",
                             std::to_string(kMaxWordWeight), "]"}));
    }
  }
  Corpus out(corpus.num_words(), corpus.vocabulary());
  std::vector<std::int32_t> counts;
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const DocumentView doc = corpus.document(d);
    counts.assign(doc.counts.begin(), doc.counts.end());
    for (std::size_t i = 0; i < counts.size(); ++i) {
      const std::int32_t w = weights[static_cast<std::size_t>(doc.words[i])];
      if (counts[i] > std::numeric_limits<std::int32_t>::max() / w) {
        throw Error(core::cat({"weighted_by: document ", std::to_string(d), ": ",
                               std::to_string(counts[i]), " x word ", std::to_string(doc.words[i]),
                               " weighing ", std::to_string(w), " overflows a count"}));
      }
      counts[i] *= w;
    }
    out.add_document(doc.words, counts);
  }
  return out;
}

std::vector<std::int32_t> weights_from(int num_words, int first, int weight) {
  if (num_words < 0 || first < 0 || first > num_words || weight < 1 || weight > kMaxWordWeight) {
    throw Error(core::cat({"weights_from: first word ", std::to_string(first), " of ",
                           std::to_string(num_words), ", weight ", std::to_string(weight)}));
  }
  std::vector<std::int32_t> w(static_cast<std::size_t>(num_words), 1);
  std::fill(w.begin() + first, w.end(), weight);
  return w;
}

Corpus weighted_from(const Corpus& corpus, int first, int weight) {
  const std::vector<std::int32_t> w = weights_from(corpus.num_words(), first, weight);
  return weight == 1 ? corpus : weighted_by(corpus, w);
}

}  // namespace proprio::topics
