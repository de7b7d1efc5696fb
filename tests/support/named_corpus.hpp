#pragma once
// A synthetic corpus with a vocabulary (word0, word1, ...), as the UCI format needs one.

#include <string>
#include <vector>

#include "proprio/topics/corpus.hpp"
#include "proprio/topics/synthetic.hpp"

namespace proprio::test {

/// make_synthetic_corpus(options)'s corpus with its words named "word0", "word1", ...
inline topics::Corpus named_synthetic_corpus(const topics::SyntheticCorpusOptions& options) {
  const topics::Corpus c = topics::make_synthetic_corpus(options).corpus;
  std::vector<std::string> vocab;
  for (int w = 0; w < options.num_words; ++w) vocab.push_back("word" + std::to_string(w));
  topics::Corpus named(options.num_words, vocab);
  for (std::size_t d = 0; d < c.num_documents(); ++d) {
    const auto doc = c.document(d);
    named.add_document(doc.words, doc.counts);
  }
  return named;
}

}  // namespace proprio::test
