// proprio recognize ... and proprio experiment ...: objects learned as topics of visual words
// (thesis Ch 6, 7.3.1): LDA from image folders or episodes, classification, and the experiments
// of 6.3 (specific vs wide dictionary, batch vs online LDA, videos of objects moved about).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/episode_classification.hpp"
#include "proprio/recognition/experiments.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using namespace recognition;

// Episode directories: each argument is an episode (it holds episode.json) or a directory of
// episodes (its sub-directories that hold one, sorted by name).
std::vector<episode::Episode> read_episodes(const std::vector<std::string>& args) {
  std::vector<episode::Episode> out;
  for (const fs::path& d : episode::find_episodes({args.begin(), args.end()}))
    out.push_back(episode::read_episode(d));
  return out;
}

// The feature options of every command that extracts features: one description,
// features::ExtractOptions (the same flags as `vocab build` and `vocab quantize`).
void add_feature_options(CLI::App* cmd, features::ExtractOptions& o) { bind_options(cmd, o); }

ProgressFn progress_of(std::shared_ptr<core::ProgressBar>& bar, const char* label, bool quiet) {
  return [&bar, label, quiet](std::size_t done, std::size_t total) {
    if (quiet) return;
    if (!bar || done == 1) bar = std::make_shared<core::ProgressBar>(total, label);
    bar->tick();
    if (done == total) bar->finish();
  };
}

std::vector<int> parse_topics(const std::string& text) {
  std::vector<int> ks;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, end - start);
    std::size_t used = 0;
    int k = -1;
    if (item == "objects") {
      ks.push_back(0);
      start = end + 1;
      continue;
    }
    try {
      k = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty() || k < 1) {
      std::string m = "--k: '";
      m += item;
      m += "' is not a number of topics >= 1 (or 'objects')";
      throw Error(m);
    }
    ks.push_back(k);
    start = end + 1;
  }
  return ks;
}

void print_evaluation(const std::string& title, const Evaluation& e) {
  std::printf("%s: topics (argmax theta; rows: true class)\n%s", title.c_str(),
              e.topics.format().c_str());
  std::printf("topic -> class (from the labelled training images):");
  for (std::size_t k = 0; k < e.mapping.topic_class.size(); ++k)
    std::printf(" z_%zu->%s", k + 1,
                e.classes.columns[static_cast<std::size_t>(e.mapping.topic_class[k])].c_str());
  std::printf("\n%s: classes (topics merged)\n%s", title.c_str(), e.classes.format().c_str());
  std::printf("%s: accuracy %.1f%%, mean class accuracy %.1f%%\n\n", title.c_str(),
              100 * e.classes.accuracy(), 100 * e.classes.mean_class_accuracy());
}

core::Json kmeans_json(const features::KmeansSummary& s, int descriptors) {
  core::Json j;
  j["descriptors"] = descriptors;
  j["iterations"] = s.iterations;
  j["cost"] = s.cost;
  j["seconds"] = s.seconds;
  j["termination"] = s.termination;
  return j;
}

// ---- recognize train / classify ----

struct TrainArgs {
  std::string images;
  std::vector<std::string> episodes;
  std::string vocabulary;
  std::string model;
  std::string json;
  std::string method = "online";
  std::string region = "whole";
  std::vector<std::string> objects;
  std::string masks;
  int frame_step = 1;
  features::ExtractOptions features;
  topics::OnlineLdaOptions online;
  int max_iterations = 100;
  bool quiet = false;
};

void run_train(const TrainArgs& a, const Invocation& inv) {
  if (a.images.empty() == a.episodes.empty()) {
    throw Error("give either --images DIR or --episodes DIR...");
  }
  if (a.online.num_topics < 1) throw Error("the number of topics K must be >= 1");
  const features::Vocabulary vocabulary = features::read_vocabulary(a.vocabulary);
  std::shared_ptr<core::ProgressBar> bar;
  topics::Corpus corpus(vocabulary.size());
  int frames = 0;
  if (!a.images.empty()) {
    const features::ImageSet set = features::read_image_set(a.images);
    std::vector<std::size_t> all(set.images.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    corpus =
        image_corpus(set, all, vocabulary, a.features, progress_of(bar, "images", a.quiet)).corpus;
  } else {
    FrameDocumentOptions fo;
    fo.region = parse_frame_region(a.region);
    fo.objects = a.objects;
    fo.masks = a.masks;
    fo.features = a.features;
    fo.validate();
    if (a.frame_step < 1) throw Error("--frame-step must be >= 1");
    for (const auto& e : read_episodes(a.episodes)) {
      for (int i = 0; i < e.frame_count(); i += a.frame_step) {
        for (const auto& f : frame_features(e, i, fo))
          if (!f.empty()) corpus.add_tokens(features::bag_of_words(vocabulary, f.descriptors));
        ++frames;
      }
    }
  }
  if (corpus.num_documents() == 0 || corpus.num_tokens() == 0) {
    throw Error("no features to learn from (every document is empty)");
  }
  topics::LdaModel model;
  std::string summary;
  if (a.method == "online") {
    auto r = topics::train_online_lda(corpus, a.online);
    model = std::move(r.model);
    summary = r.summary.brief();
  } else {
    topics::BatchLdaOptions b;
    b.num_topics = a.online.num_topics;
    b.seed = a.online.seed;
    b.max_iterations = a.max_iterations;
    auto r = topics::train_batch_lda(corpus, b);
    model = std::move(r.model);
    summary = r.summary.brief();
  }
  topics::save_lda_model(model, a.model);
  std::printf("%s\ndocuments: %zu\ntokens: %lld\nmodel: %s\n", summary.c_str(),
              corpus.num_documents(), static_cast<long long>(corpus.num_tokens()), a.model.c_str());
  core::Json doc =
      core::result_document("proprio.recognize.train", 1, inv.provenance(a.online.seed));
  doc["model"] = a.model;
  doc["vocabulary"] = a.vocabulary;
  doc["source"] = a.images.empty() ? "episodes" : "images";
  doc["method"] = a.method;
  doc["topics"] = model.num_topics();
  doc["words"] = model.num_words();
  doc["documents"] = corpus.num_documents();
  doc["tokens"] = corpus.num_tokens();
  doc["frames"] = frames;
  doc["summary"] = summary;
  write_json_result(a.json, doc);
}

struct ClassifyArgs {
  std::string model;
  std::string vocabulary;
  std::string images;
  std::vector<std::string> episodes;
  std::string region = "whole";
  std::vector<std::string> objects;
  std::string masks;
  int frame_step = 1;
  std::string map_with;
  std::string out;
  std::string json;
  features::ExtractOptions features;
  bool quiet = false;
};

// The topic mapping from labelled folder-per-class images (never the test data).
Evaluation mapping_from_images(const topics::LdaModel& model, const features::Vocabulary& v,
                               const features::ImageSet& known, const features::ExtractOptions& fo,
                               const ProgressFn& progress) {
  std::vector<std::size_t> kall(known.images.size());
  std::iota(kall.begin(), kall.end(), std::size_t{0});
  const LabelledCorpus labelled = image_corpus(known, kall, v, fo, progress);
  return evaluate_model(model, labelled, labelled);
}

void run_classify_episodes(const ClassifyArgs& a, const Invocation& inv,
                           const topics::LdaModel& model, const features::Vocabulary& vocabulary) {
  EpisodeClassifyOptions o;
  o.frames.region = parse_frame_region(a.region);
  o.frames.objects = a.objects;
  o.frames.masks = a.masks;
  o.frames.features = a.features;
  o.frame_step = a.frame_step;
  const std::vector<episode::Episode> episodes = read_episodes(a.episodes);
  std::shared_ptr<core::ProgressBar> bar;
  EpisodeClassification r =
      classify_episodes(episodes, model, vocabulary, o, progress_of(bar, "frames", a.quiet));
  std::printf("%s (%lld empty)\n", r.summary.message.c_str(),
              static_cast<long long>(r.summary.empty_documents));
  core::Json doc = core::result_document("proprio.recognize.classify", 1, inv.provenance());
  doc["model"] = a.model;
  doc["episodes"] = a.episodes;
  doc["region"] = a.region;
  doc["frame_step"] = a.frame_step;
  doc["frames"] = r.summary.frames;
  doc["documents"] = r.summary.documents;
  doc["empty_documents"] = r.summary.empty_documents;
  if (r.by_topic) {
    std::printf("topics (argmax theta; rows: true object by the ground-truth masks)\n%s",
                r.by_topic->format().c_str());
    doc["topics"] = r.by_topic->to_json();
  }
  std::vector<std::string> mapping_classes;
  if (!a.map_with.empty()) {
    const features::ImageSet known = features::read_image_set(a.map_with);
    mapping_classes = known.classes;
    const Evaluation e = mapping_from_images(model, vocabulary, known, o.frames.features,
                                             progress_of(bar, "labelled", a.quiet));
    const ConfusionMatrix classes = apply_mapping(r, e.mapping, mapping_classes);
    std::printf("topic -> class (from the labelled images of %s):", a.map_with.c_str());
    for (std::size_t k = 0; k < e.mapping.topic_class.size(); ++k)
      std::printf(" z_%zu->%s", k + 1,
                  mapping_classes[static_cast<std::size_t>(e.mapping.topic_class[k])].c_str());
    std::printf("\n");
    doc["mapping"] = evaluation_to_json(e)["mapping"];
    if (!r.classes.empty()) {
      std::printf("classes (topics merged)\n%s", classes.format().c_str());
      std::printf("accuracy %.1f%%, mean class accuracy %.1f%%\n", 100 * classes.accuracy(),
                  100 * classes.mean_class_accuracy());
      doc["classes"] = classes.to_json();
    }
  }
  if (!a.out.empty()) {
    std::string csv = "episode,frame,document,truth,topic,class";
    for (int k = 0; k < model.num_topics(); ++k) {
      csv += ",theta_";
      csv += std::to_string(k);
    }
    csv += '\n';
    for (std::size_t d = 0; d < r.documents.size(); ++d) {
      const ClassifiedDocument& c = r.documents[d];
      csv += episodes[static_cast<std::size_t>(c.episode)].dir().string();
      csv += ',' + std::to_string(c.frame);
      csv += ',' + std::to_string(c.document) + ',';
      if (c.truth >= 0) csv += r.classes[static_cast<std::size_t>(c.truth)];
      csv += ',';
      if (c.topic >= 0) csv += std::to_string(c.topic);
      csv += ',';
      if (c.mapped >= 0) csv += mapping_classes[static_cast<std::size_t>(c.mapped)];
      for (int k = 0; k < model.num_topics(); ++k) {
        char buf[32];
        std::snprintf(buf, sizeof buf, ",%.6g", r.theta(static_cast<Eigen::Index>(d), k));
        csv += buf;
      }
      csv += '\n';
    }
    core::write_file_atomic(a.out, csv);
    doc["out"] = a.out;
  }
  write_json_result(a.json, doc);
}

void run_classify(const ClassifyArgs& a, const Invocation& inv) {
  if (a.images.empty() == a.episodes.empty()) {
    throw Error("give either --images DIR or --episodes DIR...");
  }
  const topics::LdaModel model = topics::load_lda_model(a.model);
  const features::Vocabulary vocabulary = features::read_vocabulary(a.vocabulary);
  if (model.num_words() != vocabulary.size()) {
    std::string m = "the model has ";
    m += std::to_string(model.num_words());
    m += " words but the vocabulary ";
    m += std::to_string(vocabulary.size());
    throw Error::in_file(a.model, m);
  }
  if (!a.episodes.empty()) {
    run_classify_episodes(a, inv, model, vocabulary);
    return;
  }
  const features::ExtractOptions fo = a.features;
  std::shared_ptr<core::ProgressBar> bar;
  const features::ImageSet set = features::read_image_set(a.images);
  std::vector<std::size_t> all(set.images.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  const LabelledCorpus test =
      image_corpus(set, all, vocabulary, fo, progress_of(bar, "images", a.quiet));
  const topics::InferenceResult r = topics::infer_topics(model, test.corpus);
  const std::vector<int> topic = r.classify();
  const ConfusionMatrix by_topic =
      confusion_matrix(test.labels, topic, test.classes, topic_names(model.num_topics()));
  std::printf("topics (argmax theta; rows: folder)\n%s", by_topic.format().c_str());
  core::Json doc = core::result_document("proprio.recognize.classify", 1, inv.provenance());
  doc["model"] = a.model;
  doc["images"] = a.images;
  doc["documents"] = test.corpus.num_documents();
  doc["empty_documents"] = r.summary.empty_documents;
  doc["topics"] = by_topic.to_json();
  std::vector<int> mapped;
  if (!a.map_with.empty()) {
    const features::ImageSet known = features::read_image_set(a.map_with);
    if (known.classes != set.classes) {
      throw Error::in_file(a.map_with, "its class folders differ from those of --images");
    }
    std::vector<std::size_t> kall(known.images.size());
    std::iota(kall.begin(), kall.end(), std::size_t{0});
    const LabelledCorpus labelled =
        image_corpus(known, kall, vocabulary, fo, progress_of(bar, "labelled", a.quiet));
    const Evaluation e = evaluate_model(model, labelled, test);
    print_evaluation("classification", e);
    mapped = mapped_classes(topic, e.mapping);
    doc["mapped"] = evaluation_to_json(e);
  }
  if (!a.out.empty()) {
    std::string csv = "image,truth,topic,class";
    for (int k = 0; k < model.num_topics(); ++k) {
      csv += ",theta_";
      csv += std::to_string(k);
    }
    csv += '\n';
    const Eigen::MatrixXd theta = r.theta();
    for (std::size_t d = 0; d < all.size(); ++d) {
      csv += set.images[d].string();
      csv += ',';
      csv += set.classes[static_cast<std::size_t>(test.labels[d])];
      csv += ',';
      csv += std::to_string(topic[d]);
      csv += ',';
      csv +=
          mapped.empty() || mapped[d] < 0 ? "" : set.classes[static_cast<std::size_t>(mapped[d])];
      for (int k = 0; k < model.num_topics(); ++k) {
        char buf[32];
        std::snprintf(buf, sizeof buf, ",%.6g", theta(static_cast<Eigen::Index>(d), k));
        csv += buf;
      }
      csv += '\n';
    }
    core::write_file_atomic(a.out, csv);
    doc["out"] = a.out;
  }
  write_json_result(a.json, doc);
}

// ---- experiment dictionary / batch-online ----

struct SetArgs {
  std::string images;
  std::vector<std::string> set_a, set_b, wide;
  SetExperimentOptions options;
  features::ExtractOptions features;
  int lda_iterations = 100;
  int online_passes = 10;
  int online_batch = 50;
  std::string json;
  bool quiet = false;
};

void run_set(SetArgs& a, const Invocation& inv, bool dictionary) {
  SetExperimentOptions o = a.options;
  o.set_a = a.set_a;
  o.set_b = a.set_b;
  o.wide = a.wide;
  o.features = a.features;
  o.runs = dictionary ? dictionary_runs() : batch_online_runs();
  o.batch.max_iterations = a.lda_iterations;
  o.batch.seed = o.seed;
  o.online.passes = a.online_passes;
  o.online.batch_size = a.online_batch;
  o.online.seed = o.seed;
  o.kmeans.seed = o.seed;
  const features::ImageSet set = features::read_image_set(a.images);
  std::shared_ptr<core::ProgressBar> bar;
  const SetExperimentResult r = run_set_experiment(set, o, progress_of(bar, "images", a.quiet));
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
    return s;
  };
  std::printf("set A: %s\nset B: %s\nwide dictionary: %s\n\n", join(r.set_a).c_str(),
              join(r.set_b).c_str(), join(r.wide).c_str());
  const char* format =
      dictionary ? "proprio.experiment.dictionary" : "proprio.experiment.batch_online";
  core::Json doc = core::result_document(format, 1, inv.provenance(o.seed));
  doc["images"] = a.images;
  doc["set_a"] = r.set_a;
  doc["set_b"] = r.set_b;
  doc["wide"] = r.wide;
  doc["words"] = o.kmeans.words;
  doc["test_per_class"] = o.test_per_class;
  doc["features"] = features::to_string(o.features.kind);
  if (r.specific_kmeans)
    doc["specific_dictionary"] = kmeans_json(*r.specific_kmeans, r.specific_descriptors);
  if (r.wide_kmeans) doc["wide_dictionary"] = kmeans_json(*r.wide_kmeans, r.wide_descriptors);
  doc["runs"] = core::Json::array();
  for (const SetRunResult& run : r.runs) {
    std::string title = run.run.name;
    title += " (set ";
    title += run.run.set;
    title += ", ";
    title += run.run.dictionary;
    title += " dictionary, ";
    title += to_string(run.run.method);
    title += " LDA)";
    print_evaluation(title, run.evaluation);
    core::Json j = evaluation_to_json(run.evaluation);
    j["name"] = run.run.name;
    j["set"] = run.run.set;
    j["dictionary"] = run.run.dictionary;
    j["method"] = to_string(run.run.method);
    j["train_documents"] = run.train_documents;
    j["test_documents"] = run.test_documents;
    j["train_seconds"] = run.train_seconds;
    j["lda_summary"] = run.lda_summary;
    doc["runs"].push_back(j);
  }
  std::printf("seconds: %.1f\n", r.seconds);
  doc["seconds"] = r.seconds;
  write_json_result(a.json, doc);
}

void add_set_options(CLI::App* cmd, SetArgs& a) {
  cmd->add_option("--images", a.images, "Folder-per-class image set (Caltech-256's layout)")
      ->required();
  cmd->add_option("--set-a", a.set_a,
                  "Classes of set A (the specific dictionary's); default: the first half")
      ->delimiter(',');
  cmd->add_option("--set-b", a.set_b, "Classes of set B; default: the other half")->delimiter(',');
  cmd->add_option("--wide", a.wide, "Classes of the wide dictionary; default: all")->delimiter(',');
  cmd->add_option("--words", a.options.kmeans.words, "Words per dictionary")->capture_default_str();
  cmd->add_option("--dictionary-images", a.options.dictionary_images,
                  "Training images per class for a dictionary")
      ->capture_default_str();
  cmd->add_option("--per-image", a.options.descriptors_per_image,
                  "Descriptors drawn per dictionary image")
      ->capture_default_str();
  cmd->add_option("--test-per-class", a.options.test_per_class, "Test images per class")
      ->capture_default_str();
  cmd->add_option("--lda-iterations", a.lda_iterations, "Batch LDA: EM iterations at most")
      ->capture_default_str();
  cmd->add_option("--passes", a.online_passes, "Online LDA: passes over the training images")
      ->capture_default_str();
  cmd->add_option("--batch", a.online_batch, "Online LDA: images per mini-batch")
      ->capture_default_str();
  cmd->add_option("--seed", a.options.seed, "Seed of the split, dictionaries and LDA")
      ->capture_default_str();
  add_feature_options(cmd, a.features);
  cmd->add_flag("-q,--quiet", a.quiet, "No progress bar");
  cmd->add_option("--json", a.json, "Also write the confusion matrices as JSON");
}

// ---- experiment scatter ----

struct ScatterArgs {
  std::vector<std::string> episodes;
  std::string views;
  std::vector<std::string> view_episodes;
  std::vector<std::string> objects;
  std::string vocabulary;
  std::string k = "objects,8";
  std::string region = "objects";
  std::string masks;
  ScatterExperimentOptions options;
  features::ExtractOptions features;
  std::string json;
  bool quiet = false;
};

void run_scatter(ScatterArgs& a, const Invocation& inv) {
  ScatterExperimentOptions o = a.options;
  o.topics.clear();
  o.topics = parse_topics(a.k);
  o.frames.region = parse_frame_region(a.region);
  o.frames.masks = a.masks;
  o.frames.features = a.features;
  o.view_features = o.frames.features;
  o.frames.features.center_crop = 1.0;  // frames: the region decides
  o.kmeans.seed = o.seed;
  if (a.views.empty() == a.view_episodes.empty()) {
    throw Error("give either --views DIR or --view-episodes DIR... (with --objects)");
  }
  if (!a.view_episodes.empty() && a.objects.empty()) {
    throw Error("--view-episodes needs --objects (the objects whose views are cut from them)");
  }
  const std::vector<episode::Episode> episodes = read_episodes(a.episodes);
  std::optional<features::Vocabulary> vocabulary;
  if (!a.vocabulary.empty()) vocabulary = features::read_vocabulary(a.vocabulary);
  std::shared_ptr<core::ProgressBar> bar;
  ScatterExperimentResult r;
  if (a.views.empty()) {
    // Segmented views: the features inside each object's mask; no centre crop.
    o.view_features.center_crop = 1.0;
    r = run_scatter_experiment(episodes, read_episodes(a.view_episodes), a.objects, o,
                               vocabulary ? &*vocabulary : nullptr,
                               progress_of(bar, "frames", a.quiet));
  } else {
    const features::ImageSet views = features::read_image_set(a.views);
    r = run_scatter_experiment(episodes, views, o, vocabulary ? &*vocabulary : nullptr,
                               progress_of(bar, "frames", a.quiet));
  }
  std::printf("objects: %zu, episodes: %zu, frames: %d, documents: %d, tokens: %lld, words: %d\n",
              r.objects.size(), episodes.size(), r.frames, r.documents,
              static_cast<long long>(r.tokens), r.words);
  std::printf("mini-batches: %d documents (%d frames)\n", r.batch_documents, o.online.batch_size);
  std::printf("views: %d name the topics (labelled), %d test\n\n", r.mapping_views, r.test_views);
  core::Json doc = core::result_document("proprio.experiment.scatter", 1, inv.provenance(o.seed));
  doc["episodes"] = a.episodes;
  if (!a.views.empty()) doc["views"] = a.views;
  if (!a.view_episodes.empty()) {
    doc["view_episodes"] = a.view_episodes;
    doc["view_step"] = o.view_step;
    doc["view_block"] = o.view_block;
    doc["view_split"] = o.split_by_episode ? "episodes" : "blocks";
  }
  doc["mot"] = o.mot;
  doc["objects"] = r.objects;
  doc["region"] = a.region;
  doc["features"] = features::to_string(o.frames.features.kind);
  doc["frames"] = r.frames;
  doc["documents"] = r.documents;
  doc["tokens"] = r.tokens;
  doc["words"] = r.words;
  doc["batch_size"] = o.online.batch_size;
  doc["batch_documents"] = r.batch_documents;
  doc["passes"] = o.online.passes;
  doc["mapping_views"] = r.mapping_views;
  doc["test_views"] = r.test_views;
  if (r.kmeans) doc["dictionary"] = kmeans_json(*r.kmeans, r.dictionary_descriptors);
  doc["runs"] = core::Json::array();
  for (const ScatterRunResult& run : r.runs) {
    std::string title = "K = ";
    title += std::to_string(run.topics);
    print_evaluation(title, run.evaluation);
    core::Json j = evaluation_to_json(run.evaluation);
    j["topics_k"] = run.topics;
    j["updates"] = run.summary.updates;
    j["train_seconds"] = run.summary.seconds;
    if (run.mot) {
      std::printf("%s: Mixture of Topics (supervised, thesis 7.1; rows: true object)\n%s",
                  title.c_str(), run.mot->classes.format().c_str());
      std::printf("%s: Mixture of Topics accuracy %.1f%%, mean class accuracy %.1f%%\n\n",
                  title.c_str(), 100 * run.mot->classes.accuracy(),
                  100 * run.mot->classes.mean_class_accuracy());
      j["mot"] = run.mot->classes.to_json();
      j["mot"]["summary"] = run.mot->fit.summary.brief();
    }
    if (run.mot_unsupervised) {
      const MotUnsupervisedEvaluation& u = *run.mot_unsupervised;
      std::printf(
          "%s: Mixture of Topics, unsupervised (k-means over theta, C = %zu; objects named "
          "by the labelled views; BIC would choose C = %d)\n%s",
          title.c_str(), r.objects.size(), u.chosen_classes, u.classes.format().c_str());
      std::printf(
          "%s: unsupervised Mixture of Topics accuracy %.1f%%, mean class accuracy %.1f%%\n\n",
          title.c_str(), 100 * u.classes.accuracy(), 100 * u.classes.mean_class_accuracy());
      j["mot_unsupervised"] = u.classes.to_json();
      j["mot_unsupervised"]["chosen_classes"] = u.chosen_classes;
      j["mot_unsupervised"]["object_class"] = u.object_class;
    }
    doc["runs"].push_back(j);
  }
  std::printf("seconds: %.1f\n", r.seconds);
  doc["seconds"] = r.seconds;
  write_json_result(a.json, doc);
}

}  // namespace

void register_recognition_commands(CLI::App& root, const Invocation& inv) {
  auto* rec = root.add_subcommand(
      "recognize", "Objects as topics of visual words: learn and classify (thesis Ch 6)");
  rec->require_subcommand(1);

  auto t = std::make_shared<TrainArgs>();
  auto* train = rec->add_subcommand(
      "train", "Learn LDA from an image folder (an image a document) or from episodes");
  train->add_option("--images", t->images, "Folder-per-class images (labels are not used)");
  train->add_option("--episodes", t->episodes, "Episode directories, or directories of them");
  train->add_option("--vocabulary", t->vocabulary, "Vocabulary file (proprio vocab build)")
      ->required();
  train->add_option("--model", t->model, "Model file to write")->required();
  train->add_option("-k,--topics", t->online.num_topics, "Number of topics K")
      ->capture_default_str();
  train->add_option("--method", t->method, "online or batch")
      ->check(CLI::IsMember({"online", "batch"}))
      ->capture_default_str();
  t->online.batch_size = 50;
  train->add_option("--batch", t->online.batch_size, "Documents per mini-batch (online)")
      ->capture_default_str();
  train->add_option("--passes", t->online.passes, "Passes (online)")->capture_default_str();
  train->add_option("--max-iterations", t->max_iterations, "EM iterations (batch)")
      ->capture_default_str();
  train->add_option("--seed", t->online.seed, "Seed")->capture_default_str();
  train
      ->add_option(
          "--region", t->region,
          "Episodes: whole, target, objects (ground-truth masks), blobs, masks, each-object")
      ->capture_default_str();
  train->add_option("--objects", t->objects, "Episodes, region objects: object names")
      ->delimiter(',');
  train->add_option("--masks", t->masks, "Episodes, region masks: directory of masks");
  train->add_option("--frame-step", t->frame_step, "Episodes: every n-th frame")
      ->capture_default_str();
  add_feature_options(train, t->features);
  train->add_flag("-q,--quiet", t->quiet, "No progress bar");
  train->add_option("--json", t->json, "Also write a summary as JSON");
  train->callback([t, &inv] { run_train(*t, inv); });

  auto c = std::make_shared<ClassifyArgs>();
  auto* cls = rec->add_subcommand(
      "classify",
      "Classify folder-per-class images or episodes' frames by argmax theta (thesis 6.1.4)");
  cls->add_option("--model", c->model, "Model file")->required();
  cls->add_option("--vocabulary", c->vocabulary, "The model's vocabulary file")->required();
  cls->add_option("--images", c->images, "Folder-per-class images to classify");
  cls->add_option("--episodes", c->episodes,
                  "Episode directories, or directories of them: classify their frames");
  cls->add_option(
         "--region", c->region,
         "Episodes: whole, target, objects (ground-truth masks), blobs, masks, each-object")
      ->capture_default_str();
  cls->add_option("--objects", c->objects, "Episodes, region objects: object names")
      ->delimiter(',');
  cls->add_option("--masks", c->masks, "Episodes, region masks: directory of masks");
  cls->add_option("--frame-step", c->frame_step, "Episodes: every n-th frame")
      ->capture_default_str();
  cls->add_option("--map-with", c->map_with,
                  "Labelled folder-per-class images that name the topics (never the test images)");
  cls->add_option("--out", c->out,
                  "CSV: image, truth, topic, class, theta_0..theta_{K-1} (episodes: episode, "
                  "frame, document, truth, topic, class, theta_k)");
  add_feature_options(cls, c->features);
  cls->add_flag("-q,--quiet", c->quiet, "No progress bar");
  cls->add_option("--json", c->json, "Also write the confusion matrices as JSON");
  cls->callback([c, &inv] { run_classify(*c, inv); });

  auto* exp = root.add_subcommand("experiment", "Rerun the thesis's object-modelling experiments");
  exp->require_subcommand(1);
  auto d = std::make_shared<SetArgs>();
  auto* dict = exp->add_subcommand(
      "dictionary", "Specific vs wide dictionary (thesis 6.3.1, Tables 6.1-6.2), batch LDA");
  add_set_options(dict, *d);
  dict->callback([d, &inv] { run_set(*d, inv, true); });
  auto b = std::make_shared<SetArgs>();
  auto* bo = exp->add_subcommand(
      "batch-online", "Batch vs online LDA with the wide dictionary (thesis 6.3.2, Table 6.3)");
  add_set_options(bo, *b);
  bo->callback([b, &inv] { run_set(*b, inv, false); });

  auto s = std::make_shared<ScatterArgs>();
  auto* sc = exp->add_subcommand(
      "scatter",
      "Online LDA on videos of objects moved about; classify held-out views (6.3.3, 7.3.1)");
  sc->add_option("--episodes", s->episodes, "Episode directories, or directories of them")
      ->required();
  sc->add_option("--views", s->views, "Folder-per-object views; folder names = object names");
  sc->add_option("--view-episodes", s->view_episodes,
                 "Held-out episodes whose frames, cut by the ground-truth masks, give the views "
                 "(alternate blocks of --view-block frames name the topics and test); instead "
                 "of --views");
  sc->add_option("--view-block", s->options.view_block,
                 "With --view-episodes: frames per block of the naming / test split")
      ->capture_default_str();
  sc->add_option("--objects", s->objects, "With --view-episodes: the objects (catalogue names)")
      ->delimiter(',');
  sc->add_option("--view-step", s->options.view_step, "With --view-episodes: every n-th frame")
      ->capture_default_str();
  sc->add_option("--view-min-features", s->options.view_min_features,
                 "With --view-episodes: least features of a view")
      ->capture_default_str();
  sc->add_option("--k", s->k,
                 "Numbers of topics K, comma-separated; objects = the number of objects")
      ->capture_default_str();
  sc->add_option("--vocabulary", s->vocabulary, "Vocabulary file (default: built from the frames)");
  sc->add_option("--words", s->options.kmeans.words, "Words of a dictionary built from the frames")
      ->capture_default_str();
  sc->add_option("--dictionary-frames", s->options.dictionary_frames,
                 "Frames sampled for that dictionary")
      ->capture_default_str();
  sc->add_option("--per-frame", s->options.descriptors_per_frame, "Descriptors drawn per frame")
      ->capture_default_str();
  sc->add_option(
        "--region", s->region,
        "What of a frame is a document: objects (the views' objects by the ground-truth "
        "masks), each-object (one document per object, masks), whole, target, blobs, masks")
      ->capture_default_str();
  sc->add_option("--masks", s->masks, "Region masks: directory of masks");
  sc->add_option("--frame-step", s->options.frame_step, "Use every n-th frame")
      ->capture_default_str();
  sc->add_option("--batch", s->options.online.batch_size, "Frames per mini-batch")
      ->capture_default_str();
  sc->add_option("--passes", s->options.online.passes, "Passes over the frames")
      ->capture_default_str();
  sc->add_option("--mapping-fraction", s->options.mapping_fraction,
                 "Fraction of each object's views (labelled) that names the topics; the rest test")
      ->capture_default_str();
  sc->add_option("--seed", s->options.seed, "Seed")->capture_default_str();
  sc->add_flag("--split-by-episode", s->options.split_by_episode,
               "With --view-episodes: the first --mapping-fraction of the view episodes give the "
               "labelled views, the others the test views (instead of alternate blocks)");
  sc->add_flag("--mot", s->options.mot,
               "Also classify the test views by a supervised Mixture of Topics (thesis 7.1) "
               "fitted to the labelled views' theta");
  add_feature_options(sc, s->features);
  sc->add_flag("-q,--quiet", s->quiet, "No progress bar");
  sc->add_option("--json", s->json, "Also write the confusion matrices as JSON");
  sc->callback([s, &inv] { run_scatter(*s, inv); });
}

}  // namespace proprio::app
