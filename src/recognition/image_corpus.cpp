#include "proprio/recognition/image_corpus.hpp"

#include <algorithm>
#include <cassert>
#include <numeric>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"

namespace proprio::recognition {

namespace {

// Draws min(n, size) distinct indices of [0, size) (partial Fisher-Yates), sorted.
std::vector<std::size_t> draw(std::size_t size, std::size_t n, core::Rng& rng) {
  std::vector<std::size_t> all(size);
  std::iota(all.begin(), all.end(), std::size_t{0});
  n = std::min(n, size);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = i + static_cast<std::size_t>(rng.index(size - i));
    std::swap(all[i], all[j]);
  }
  all.resize(n);
  std::sort(all.begin(), all.end());
  return all;
}

std::vector<std::vector<std::size_t>> by_class(const features::ImageSet& set,
                                               std::span<const std::size_t> indices) {
  std::vector<std::vector<std::size_t>> out(set.classes.size());
  for (std::size_t i : indices) out[static_cast<std::size_t>(set.labels[i])].push_back(i);
  return out;
}

}  // namespace

LabelledCorpus image_corpus(const features::ImageSet& set, std::span<const std::size_t> indices,
                            const features::Vocabulary& vocabulary,
                            const features::ExtractOptions& options, const ProgressFn& progress) {
  LabelledCorpus out;
  out.corpus = topics::Corpus(vocabulary.size());
  out.classes = set.classes;
  std::size_t done = 0;
  for (std::size_t i : indices) {
    const features::Features f = features::extract_file_features(set.images[i], options);
    const std::vector<std::int32_t> tokens = features::bag_of_words(vocabulary, f.descriptors);
    out.corpus.add_tokens(tokens);
    out.labels.push_back(set.labels[i]);
    if (progress) progress(++done, indices.size());
  }
  return out;
}

SetSplit split_per_class(const features::ImageSet& set, int test_per_class, std::uint64_t seed) {
  if (test_per_class < 1) throw Error("the test set needs at least 1 image per class");
  std::vector<std::size_t> all(set.images.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  const auto classes = by_class(set, all);
  core::Rng rng(seed);
  SetSplit split;
  for (std::size_t c = 0; c < classes.size(); ++c) {
    const auto& members = classes[c];
    if (members.size() <= static_cast<std::size_t>(test_per_class)) {
      std::string m = "class '";
      m += set.classes[c];
      m += "' has ";
      m += std::to_string(members.size());
      m += " images; it needs more than the ";
      m += std::to_string(test_per_class);
      m += " held out for testing";
      throw Error(m);
    }
    const auto test = draw(members.size(), static_cast<std::size_t>(test_per_class), rng);
    std::size_t t = 0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      if (t < test.size() && test[t] == i) {
        split.test.push_back(members[i]);
        ++t;
      } else {
        split.train.push_back(members[i]);
      }
    }
  }
  std::sort(split.train.begin(), split.train.end());
  std::sort(split.test.begin(), split.test.end());
  return split;
}

std::vector<std::size_t> images_of(const features::ImageSet& set,
                                   std::span<const std::size_t> indices,
                                   const std::vector<std::string>& classes) {
  for (const std::string& c : classes) {
    if (std::find(set.classes.begin(), set.classes.end(), c) == set.classes.end()) {
      std::string m = "no class '";
      m += c;
      m += "' in the image set";
      throw Error(m);
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t i : indices) {
    const std::string& name = set.classes[static_cast<std::size_t>(set.labels[i])];
    if (std::find(classes.begin(), classes.end(), name) != classes.end()) out.push_back(i);
  }
  return out;
}

cv::Mat sample_descriptors(const features::ImageSet& set, std::span<const std::size_t> indices,
                           int images_per_class, int per_image,
                           const features::ExtractOptions& options, std::uint64_t seed,
                           const ProgressFn& progress) {
  if (images_per_class < 1 || per_image < 1) {
    throw Error("a dictionary needs at least 1 image per class and 1 descriptor per image");
  }
  core::Rng rng(seed);
  std::vector<std::size_t> chosen;
  for (const auto& members : by_class(set, indices)) {
    for (std::size_t i : draw(members.size(), static_cast<std::size_t>(images_per_class), rng))
      chosen.push_back(members[i]);
  }
  cv::Mat out(0, features::kDescriptorLength, CV_32F);
  std::size_t done = 0;
  for (std::size_t i : chosen) {
    const features::Features f = features::extract_file_features(set.images[i], options);
    for (std::size_t r :
         draw(static_cast<std::size_t>(f.size()), static_cast<std::size_t>(per_image), rng))
      out.push_back(f.descriptors.row(static_cast<int>(r)));
    if (progress) progress(++done, chosen.size());
  }
  if (out.rows == 0) throw Error("the dictionary images have no features");
  return out;
}

Evaluation evaluate_model(const topics::LdaModel& model, const LabelledCorpus& mapping_documents,
                          const LabelledCorpus& test, const topics::InferenceOptions& options) {
  assert(mapping_documents.classes == test.classes);
  const int n_classes = static_cast<int>(test.classes.size());
  const topics::InferenceResult known =
      topics::infer_topics(model, mapping_documents.corpus, options);
  // Empty documents say nothing about any topic: leave them out of the means.
  std::vector<int> labels = mapping_documents.labels;
  const std::vector<int> known_class = known.classify();
  for (std::size_t d = 0; d < labels.size(); ++d)
    if (known_class[d] < 0) labels[d] = -1;
  Evaluation e;
  e.mapping = map_topics(known.theta(), labels, n_classes);
  const topics::InferenceResult r = topics::infer_topics(model, test.corpus, options);
  const std::vector<int> topic = r.classify();
  e.topics = confusion_matrix(test.labels, topic, test.classes, topic_names(model.num_topics()));
  const std::vector<int> mapped = mapped_classes(topic, e.mapping);
  e.classes = confusion_matrix(test.labels, mapped, test.classes, test.classes);
  return e;
}

}  // namespace proprio::recognition
