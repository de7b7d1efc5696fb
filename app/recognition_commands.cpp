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
#include "proprio/recognition/recognize_runs.hpp"
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
  RecognizeTrainOptions options;
  std::string json;
  bool quiet = false;
};

struct ClassifyArgs {
  RecognizeClassifyOptions options;
  std::string json;
  bool quiet = false;
};

// Where documents come from: --images or --episodes, the region and the feature options.
void add_source_options(CLI::App* cmd, DocumentSource& s, const char* images_help,
                        const char* episodes_help) {
  cmd->add_option("--images", s.images, images_help);
  cmd->add_option("--episodes", s.episodes, episodes_help);
  bind_options(cmd, s);
  cmd->add_option("--objects", s.frames.objects, "Episodes, region objects: object names")
      ->delimiter(',');
  cmd->add_option("--masks", s.frames.masks, "Episodes, region masks: directory of masks");
  add_feature_options(cmd, s.frames.features);
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
    std::fputs(evaluation_report(title, run.evaluation).c_str(), stdout);
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
  }
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
    std::fputs(evaluation_report(title, run.evaluation).c_str(), stdout);
    core::Json j = evaluation_to_json(run.evaluation);
    j["topics_k"] = run.topics;
    j["updates"] = run.summary.updates;
    j["train_seconds"] = run.summary.seconds;
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
  add_source_options(train, t->options.source, "Folder-per-class images (labels are not used)",
                     "Episode directories, or directories of them");
  train->add_option("--vocabulary", t->options.vocabulary, "Vocabulary file (proprio vocab build)")
      ->required();
  train->add_option("--model", t->options.model, "Model file to write")->required();
  bind_options(train, t->options);
  t->options.online.batch_size = 50;
  bind_options(train, t->options.online, {{"topics", "batch", "passes", "seed"}, {}});
  train->add_flag("-q,--quiet", t->quiet, "No progress bar");
  train->add_option("--json", t->json, "Also write a summary as JSON");
  train->callback([t, &inv] {
    t->options.progress = !t->quiet;
    const RecognizeTrainResult r =
        run_recognize_train(t->options, inv.provenance(t->options.online.seed));
    std::fputs(r.report.c_str(), stdout);
    write_json_result(t->json, r.document);
  });

  auto c = std::make_shared<ClassifyArgs>();
  auto* cls = rec->add_subcommand(
      "classify",
      "Classify folder-per-class images or episodes' frames by argmax theta (thesis 6.1.4)");
  cls->add_option("--model", c->options.model, "Model file")->required();
  cls->add_option("--vocabulary", c->options.vocabulary, "The model's vocabulary file")->required();
  add_source_options(cls, c->options.source, "Folder-per-class images to classify",
                     "Episode directories, or directories of them: classify their frames");
  cls->add_option("--map-with", c->options.map_with,
                  "Labelled folder-per-class images that name the topics (never the test images)");
  cls->add_option("--out", c->options.out,
                  "CSV: image, truth, topic, class, theta_0..theta_{K-1} (episodes: episode, "
                  "frame, document, truth, topic, class, theta_k)");
  cls->add_flag("-q,--quiet", c->quiet, "No progress bar");
  cls->add_option("--json", c->json, "Also write the confusion matrices as JSON");
  cls->callback([c, &inv] {
    c->options.progress = !c->quiet;
    const RecognizeClassifyResult r = run_recognize_classify(c->options, inv.provenance());
    std::fputs(r.report.c_str(), stdout);
    write_json_result(c->json, r.document);
  });

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
  add_feature_options(sc, s->features);
  sc->add_flag("-q,--quiet", s->quiet, "No progress bar");
  sc->add_option("--json", s->json, "Also write the confusion matrices as JSON");
  sc->callback([s, &inv] { run_scatter(*s, inv); });
}

}  // namespace proprio::app
