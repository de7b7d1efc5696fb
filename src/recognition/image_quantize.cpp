#include "proprio/recognition/image_quantize.hpp"

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <vector>

#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/geometry/image_file.hpp"
#include "proprio/topics/corpus_io.hpp"

namespace proprio::recognition {

void QuantizeImagesOptions::validate() const {
  if (vocabulary.empty()) throw Error("vocab quantize: the vocabulary is required");
  if (images.empty()) throw Error("vocab quantize: the image set is required");
  if (corpus.empty()) throw Error("vocab quantize: the corpus directory is required");
  core::require_output_not_input(corpus, {vocabulary, images}, "--corpus");
  features.validate();
}

std::string QuantizeImagesResult::brief() const {
  char line[200];
  std::snprintf(line, sizeof line,
                "%lld documents, %ld tokens over %d words (%d images without features)",
                static_cast<long long>(corpus.num_documents()), tokens, corpus.num_words(),
                images_without_features);
  return line;
}

QuantizeImagesResult run_quantize_images(const QuantizeImagesOptions& options,
                                         const core::Provenance& provenance) {
  options.validate();
  const features::Vocabulary v = features::read_vocabulary(options.vocabulary);
  const features::ImageSet set = features::read_image_set(options.images);
  std::vector<std::string> names(static_cast<std::size_t>(v.size()));
  for (int k = 0; k < v.size(); ++k) {
    std::string& name = names[static_cast<std::size_t>(k)];
    name.assign(1, 'v');  // not `= "v"`: GCC 12's false -Wrestrict
    name += std::to_string(k);
  }
  QuantizeImagesResult r{topics::Corpus(v.size(), names), set.classes, 0, 0, {}, core::Json(), {}};
  std::vector<std::vector<std::optional<double>>> rows;
  {
    core::ProgressBar bar(set.images.size(), "images", options.progress);
    for (std::size_t i = 0; i < set.images.size(); ++i) {
      const features::Features f =
          features::extract_file_features(set.images[i], options.features, /*grey=*/true);
      bar.tick();
      if (f.descriptors.cols != v.dimension() && !f.empty()) {
        throw Error::in_file(options.vocabulary, "words of " + std::to_string(v.dimension()) +
                                                     " values; the descriptors have " +
                                                     std::to_string(f.descriptors.cols));
      }
      const auto ids = features::bag_of_words(v, f.descriptors);
      r.images_without_features += ids.empty() ? 1 : 0;
      r.tokens += static_cast<long>(ids.size());
      r.corpus.add_tokens(ids);
      rows.push_back({static_cast<double>(i + 1), static_cast<double>(set.labels[i]),
                      static_cast<double>(ids.size())});
    }
  }
  topics::write_corpus(r.corpus, options.corpus, topics::CorpusFormat::kUci);
  core::write_file_atomic(options.corpus / "labels.csv",
                          core::format_csv({"document", "label", "tokens"}, rows));
  std::string classes;
  for (const auto& c : set.classes) {
    classes += c;
    classes += '\n';
  }
  core::write_file_atomic(options.corpus / "classes.txt", classes);

  r.options = options;
  r.document = core::result_document("proprio.vocab.quantize", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace proprio::recognition
