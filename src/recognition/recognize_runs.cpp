#include "proprio/recognition/recognize_runs.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <numeric>
#include <optional>

#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/episode_classification.hpp"
#include "proprio/recognition/image_corpus.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "run_support.hpp"

namespace proprio::recognition {
namespace {

namespace fs = std::filesystem;
using detail::progress_bar;
using detail::read_episodes;

std::vector<std::size_t> every_image(const features::ImageSet& set) {
  std::vector<std::size_t> all(set.images.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  return all;
}

std::string theta_field(double x) { return core::printf_string("%.6g", x); }

std::vector<std::string> theta_header(std::vector<std::string> first, int topics) {
  for (int k = 0; k < topics; ++k) first.push_back("theta_" + std::to_string(k));
  return first;
}

void check_model_vocabulary(const topics::LdaModel& model, const features::Vocabulary& v,
                            const std::filesystem::path& model_file) {
  if (model.num_words() == v.size()) return;
  throw Error::in_file(model_file, "the model has " + std::to_string(model.num_words()) +
                                       " words but the vocabulary " + std::to_string(v.size()));
}

void classify_episodes_into(const RecognizeClassifyOptions& o, const topics::LdaModel& model,
                            const features::Vocabulary& vocabulary, RecognizeClassifyResult& out) {
  EpisodeClassifyOptions eo;
  eo.frames = o.source.frames;
  eo.frame_step = o.source.frame_step;
  const std::vector<episode::Episode> episodes = read_episodes(o.source.episodes);
  std::shared_ptr<core::ProgressBar> bar;
  EpisodeClassification r =
      classify_episodes(episodes, model, vocabulary, eo, progress_bar(bar, "frames", o.progress));
  std::string& text = out.report;
  text += core::printf_string("%s (%lld empty)\n", r.summary.message.c_str(),
                              static_cast<long long>(r.summary.empty_documents));
  std::vector<std::string>& episode_args = out.episodes.emplace(o.source.episodes.size());
  std::transform(o.source.episodes.begin(), o.source.episodes.end(), episode_args.begin(),
                 [](const std::filesystem::path& e) { return e.string(); });
  out.region = to_string(o.source.frames.region);
  out.frame_step = o.source.frame_step;
  out.frames = r.summary.frames;
  out.documents = r.summary.documents;
  out.empty_documents = r.summary.empty_documents;
  if (r.by_topic) {
    text += "topics (argmax theta; rows: true object by the ground-truth masks)\n" +
            r.by_topic->format();
    out.topics = *r.by_topic;
  }
  std::vector<std::string> mapping_classes;
  if (!o.map_with.empty()) {
    const features::ImageSet known = features::read_image_set(o.map_with);
    mapping_classes = known.classes;
    const LabelledCorpus labelled =
        image_corpus(known, every_image(known), vocabulary, eo.frames.features,
                     progress_bar(bar, "labelled", o.progress));
    const Evaluation e = evaluate_model(model, labelled, labelled);
    const ConfusionMatrix classes = apply_mapping(r, e.mapping, mapping_classes);
    text +=
        core::printf_string("topic -> class (from the labelled images of %s):", o.map_with.c_str());
    for (std::size_t k = 0; k < e.mapping.topic_class.size(); ++k)
      text += core::printf_string(
          " z_%zu->%s", k + 1,
          mapping_classes[static_cast<std::size_t>(e.mapping.topic_class[k])].c_str());
    text += "\n";
    out.mapping = e.mapping;
    if (!r.classes.empty()) {
      text += "classes (topics merged)\n" + classes.format();
      text += core::printf_string("accuracy %.1f%%, mean class accuracy %.1f%%\n",
                                  100 * classes.accuracy(), 100 * classes.mean_class_accuracy());
      out.classes = classes;
    }
  }
  if (o.out.empty()) return;
  std::string csv =
      core::join_csv_line(theta_header({"episode", "frame", "document", "truth", "topic", "class"},
                                       model.num_topics())) +
      '\n';
  for (std::size_t d = 0; d < r.documents.size(); ++d) {
    const ClassifiedDocument& c = r.documents[d];
    std::vector<std::string> row{episodes[static_cast<std::size_t>(c.episode)].dir().string(),
                                 std::to_string(c.frame), std::to_string(c.document)};
    row.push_back(c.truth >= 0 ? r.classes[static_cast<std::size_t>(c.truth)] : "");
    row.push_back(c.topic >= 0 ? std::to_string(c.topic) : "");
    row.push_back(c.mapped >= 0 ? mapping_classes[static_cast<std::size_t>(c.mapped)] : "");
    for (int k = 0; k < model.num_topics(); ++k)
      row.push_back(theta_field(r.theta(static_cast<Eigen::Index>(d), k)));
    csv += core::join_csv_line(row) + '\n';
  }
  core::write_file_atomic(o.out, csv);
  out.out = o.out;
}

void classify_images_into(const RecognizeClassifyOptions& o, const topics::LdaModel& model,
                          const features::Vocabulary& vocabulary, RecognizeClassifyResult& out) {
  std::shared_ptr<core::ProgressBar> bar;
  const features::ExtractOptions& fo = o.source.frames.features;
  const features::ImageSet set = features::read_image_set(o.source.images);
  const LabelledCorpus test =
      image_corpus(set, every_image(set), vocabulary, fo, progress_bar(bar, "images", o.progress));
  const topics::InferenceResult r = topics::infer_topics(model, test.corpus);
  const std::vector<int> topic = r.classify();
  const ConfusionMatrix by_topic =
      confusion_matrix(test.labels, topic, test.classes, topic_names(model.num_topics()));
  out.report += "topics (argmax theta; rows: folder)\n" + by_topic.format();
  out.images = o.source.images;
  out.documents = static_cast<std::int64_t>(test.corpus.num_documents());
  out.empty_documents = r.summary.empty_documents;
  out.topics = by_topic;
  std::vector<int> mapped;
  if (!o.map_with.empty()) {
    const features::ImageSet known = features::read_image_set(o.map_with);
    if (known.classes != set.classes) {
      throw Error::in_file(o.map_with, "its class folders differ from those of --images");
    }
    const LabelledCorpus labelled = image_corpus(known, every_image(known), vocabulary, fo,
                                                 progress_bar(bar, "labelled", o.progress));
    const Evaluation e = evaluate_model(model, labelled, test);
    out.report += evaluation_report("classification", e);
    mapped = mapped_classes(topic, e.mapping);
    out.mapped = e;
  }
  if (o.out.empty()) return;
  std::string csv =
      core::join_csv_line(theta_header({"image", "truth", "topic", "class"}, model.num_topics())) +
      '\n';
  const Eigen::MatrixXd theta = r.theta();
  for (std::size_t d = 0; d < set.images.size(); ++d) {
    std::vector<std::string> row{set.images[d].string(),
                                 set.classes[static_cast<std::size_t>(test.labels[d])],
                                 std::to_string(topic[d])};
    row.push_back(
        mapped.empty() || mapped[d] < 0 ? "" : set.classes[static_cast<std::size_t>(mapped[d])]);
    for (int k = 0; k < model.num_topics(); ++k)
      row.push_back(theta_field(theta(static_cast<Eigen::Index>(d), k)));
    csv += core::join_csv_line(row) + '\n';
  }
  core::write_file_atomic(o.out, csv);
  out.out = o.out;
}

}  // namespace

std::string evaluation_report(const std::string& title, const Evaluation& e) {
  std::string out = core::printf_string("%s: topics (argmax theta; rows: true class)\n%s",
                                        title.c_str(), e.topics.format().c_str());
  out += "topic -> class (from the labelled training images):";
  for (std::size_t k = 0; k < e.mapping.topic_class.size(); ++k)
    out += core::printf_string(
        " z_%zu->%s", k + 1,
        e.classes.columns[static_cast<std::size_t>(e.mapping.topic_class[k])].c_str());
  out += core::printf_string("\n%s: classes (topics merged)\n%s", title.c_str(),
                             e.classes.format().c_str());
  out += core::printf_string("%s: accuracy %.1f%%, mean class accuracy %.1f%%\n\n", title.c_str(),
                             100 * e.classes.accuracy(), 100 * e.classes.mean_class_accuracy());
  return out;
}

void DocumentSource::validate() const {
  if (images.empty() == episodes.empty())
    throw Error("give either --images DIR or --episodes DIR...");
  core::check_field_bounds(*this, "documents");
  frames.validate();
}

void RecognizeTrainOptions::validate() const {
  source.validate();
  if (vocabulary.empty() || model.empty())
    throw Error("recognize train: the vocabulary and the model file are required");
  std::vector<fs::path> inputs = source.episodes;
  inputs.push_back(source.images);
  inputs.push_back(vocabulary);
  core::require_output_not_input(model, inputs, "--model");
  core::check_field_bounds(*this, "recognize train");
  if (online.num_topics < 1) throw Error("the number of topics K must be >= 1");
  core::check_field_bounds(online, "recognize train");
  if (colour_words) {
    colour.validate();
    if (!source.images.empty()) {
      throw Error("recognize train: --colour-words is for --episodes only");
    }
  }
}

RecognizeTrainResult run_recognize_train(const RecognizeTrainOptions& options,
                                         const core::Provenance& provenance) {
  options.validate();
  const features::Vocabulary vocabulary = features::read_vocabulary(options.vocabulary);
  std::shared_ptr<core::ProgressBar> bar;
  const std::optional<features::ColourWordOptions> colour =
      features::colour_if(options.colour_words, options.colour);
  topics::Corpus corpus(features::document_vocabulary_size(vocabulary, colour));
  RecognizeTrainResult r;
  r.colour_words = options.colour_words;
  const DocumentSource& source = options.source;
  if (!source.images.empty()) {
    const features::ImageSet set = features::read_image_set(source.images);
    corpus = image_corpus(set, every_image(set), vocabulary, source.frames.features,
                          progress_bar(bar, "images", options.progress))
                 .corpus;
  } else {
    for (const auto& e : read_episodes(source.episodes)) {
      for (int i = 0; i < e.frame_count(); i += source.frame_step) {
        const cv::Mat image = e.frame(i);  // read once: the features and the colour words
        for (const auto& f : frame_features(e, i, image, source.frames))
          if (!f.empty()) corpus.add_tokens(features::document_words(vocabulary, image, f, colour));
        ++r.frames;
      }
    }
  }
  if (corpus.num_documents() == 0 || corpus.num_tokens() == 0) {
    throw Error("no features to learn from (every document is empty)");
  }
  r.colour_weight = colour ? options.colour_weight : 1;
  // The weights the model learns from are the ones it records (LdaModel::word_weights), so that
  // it reads every later document weighted alike.
  std::vector<std::int32_t> weights;
  if (r.colour_weight != 1) {
    weights = topics::weights_from(corpus.num_words(), static_cast<int>(vocabulary.size()),
                                   r.colour_weight);
    corpus = topics::weighted_by(corpus, weights);
  }
  if (options.method == topics::LdaMethod::kOnline) {
    auto t = topics::train_online_lda(corpus, options.online);
    r.model = std::move(t.model);
    r.summary = t.summary.brief();
  } else {
    topics::BatchLdaOptions b;
    b.num_topics = options.online.num_topics;
    b.seed = options.online.seed;
    b.max_iterations = options.max_iterations;
    auto t = topics::train_batch_lda(corpus, b);
    r.model = std::move(t.model);
    r.summary = t.summary.brief();
  }
  r.model.word_weights = std::move(weights);
  topics::save_lda_model(r.model, options.model);
  r.documents = corpus.num_documents();
  r.tokens = static_cast<long long>(corpus.num_tokens());
  r.report = core::printf_string("%s\ndocuments: %zu\ntokens: %lld\nmodel: %s\n", r.summary.c_str(),
                                 r.documents, r.tokens, options.model.c_str());
  r.model_file = options.model;
  r.vocabulary = options.vocabulary;
  r.source = source.images.empty() ? "episodes" : "images";
  r.method = options.method;
  r.document = core::result_document("proprio.recognize.train", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

void RecognizeClassifyOptions::validate() const {
  source.validate();
  if (model.empty() || vocabulary.empty())
    throw Error("recognize classify: the model and the vocabulary files are required");
  if (!out.empty()) {
    std::vector<fs::path> inputs = source.episodes;
    for (const auto& p : {source.images, model, vocabulary, map_with}) inputs.push_back(p);
    core::require_output_not_input(out, inputs, "--out");
  }
}

RecognizeClassifyResult run_recognize_classify(const RecognizeClassifyOptions& options,
                                               const core::Provenance& provenance) {
  options.validate();
  const topics::LdaModel model = topics::load_lda_model(options.model);
  const features::Vocabulary vocabulary = features::read_vocabulary(options.vocabulary);
  check_model_vocabulary(model, vocabulary, options.model);
  RecognizeClassifyResult out;
  out.model = options.model;
  if (!options.source.episodes.empty()) {
    classify_episodes_into(options, model, vocabulary, out);
  } else {
    classify_images_into(options, model, vocabulary, out);
  }
  out.document = core::result_document("proprio.recognize.classify", 1, provenance);
  core::fields_into_json(out, out.document);
  out.message = core::first_line(out.brief());
  return out;
}

}  // namespace proprio::recognition
