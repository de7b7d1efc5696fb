#include "proprio/recognition/experiments.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <optional>
#include <set>
#include <utility>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/recognition/episode_classification.hpp"

namespace proprio::recognition {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) {
    if (!s.empty()) s += ", ";
    s += x;
  }
  return s;
}

// Relabels a corpus of some classes of an image set to indices into `classes`.
LabelledCorpus relabel(LabelledCorpus c, const std::vector<std::string>& classes) {
  for (int& l : c.labels) {
    const std::string& name = c.classes[static_cast<std::size_t>(l)];
    l = static_cast<int>(std::find(classes.begin(), classes.end(), name) - classes.begin());
  }
  c.classes = classes;
  return c;
}

topics::LdaModel train(const topics::Corpus& corpus, LdaMethod method, int k,
                       const SetExperimentOptions& o, std::string& summary) {
  if (method == LdaMethod::kBatch) {
    topics::BatchLdaOptions b = o.batch;
    b.num_topics = k;
    auto r = topics::train_batch_lda(corpus, b);
    summary = r.summary.brief();
    return std::move(r.model);
  }
  topics::OnlineLdaOptions on = o.online;
  on.num_topics = k;
  auto r = topics::train_online_lda(corpus, on);
  summary = r.summary.brief();
  return std::move(r.model);
}

}  // namespace

std::string to_string(LdaMethod m) { return m == LdaMethod::kBatch ? "batch" : "online"; }

std::vector<SetExperimentOptions::Run> dictionary_runs() {
  return {{"C_AS", "A", "specific", LdaMethod::kBatch},
          {"C_BS", "B", "specific", LdaMethod::kBatch},
          {"C_AW", "A", "wide", LdaMethod::kBatch},
          {"C_BW", "B", "wide", LdaMethod::kBatch}};
}

std::vector<SetExperimentOptions::Run> batch_online_runs() {
  return {{"C_AW", "A", "wide", LdaMethod::kBatch},
          {"C_BW", "B", "wide", LdaMethod::kBatch},
          {"C_AO", "A", "wide", LdaMethod::kOnline},
          {"C_BO", "B", "wide", LdaMethod::kOnline}};
}

void SetExperimentOptions::validate() const {
  if (dictionary_images < 1) throw Error("dictionary images per class must be >= 1");
  if (descriptors_per_image < 1) throw Error("descriptors per image must be >= 1");
  if (test_per_class < 1) throw Error("test images per class must be >= 1");
  if (runs.empty()) throw Error("no models to train");
  kmeans.validate();
  features.validate();
  topics::BatchLdaOptions b = batch;
  b.num_topics = std::max(b.num_topics, 1);
  b.validate();
  topics::OnlineLdaOptions on = online;
  on.num_topics = std::max(on.num_topics, 1);
  on.validate();
}

SetExperimentResult run_set_experiment(const features::ImageSet& set,
                                       const SetExperimentOptions& options,
                                       const ProgressFn& progress) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  SetExperimentResult result;
  result.set_a = options.set_a;
  result.set_b = options.set_b;
  if (result.set_a.empty() && result.set_b.empty()) {
    if (set.classes.size() < 2)
      throw Error("the image set needs at least 2 classes for sets A and B");
    const std::size_t half = (set.classes.size() + 1) / 2;
    result.set_a.assign(set.classes.begin(), set.classes.begin() + static_cast<long>(half));
    result.set_b.assign(set.classes.begin() + static_cast<long>(half), set.classes.end());
  } else if (result.set_a.empty() || result.set_b.empty()) {
    throw Error("give both sets A and B, or neither");
  }
  for (const auto& a : result.set_a) {
    if (std::find(result.set_b.begin(), result.set_b.end(), a) != result.set_b.end()) {
      std::string m = "class '";
      m += a;
      m += "' is in both sets A and B";
      throw Error(m);
    }
  }
  result.wide = options.wide.empty() ? set.classes : options.wide;
  const SetSplit split = split_per_class(set, options.test_per_class, options.seed);

  // Dictionaries from training images only: the test images stay unseen by every step.
  std::optional<features::Vocabulary> specific, wide;
  auto needs = [&](const std::string& d) {
    return std::any_of(options.runs.begin(), options.runs.end(),
                       [&](const auto& r) { return r.dictionary == d; });
  };
  auto build = [&](const std::vector<std::string>& classes, std::uint64_t seed,
                   std::optional<features::KmeansSummary>& summary, int& n) {
    const cv::Mat d =
        sample_descriptors(set, images_of(set, split.train, classes), options.dictionary_images,
                           options.descriptors_per_image, options.features, seed, progress);
    n = d.rows;
    features::KmeansOptions k = options.kmeans;
    k.seed = seed;
    if (k.words > d.rows) {
      std::string m = "the dictionary needs at least as many descriptors as words (";
      m += std::to_string(d.rows);
      m += " < ";
      m += std::to_string(k.words);
      m += ")";
      throw Error(m);
    }
    auto r = features::build_vocabulary(d, k);
    summary = r.summary;
    return std::move(r.vocabulary);
  };
  if (needs("specific"))
    specific = build(result.set_a, core::stream_seed(options.seed, 1), result.specific_kmeans,
                     result.specific_descriptors);
  if (needs("wide"))
    wide = build(result.wide, core::stream_seed(options.seed, 2), result.wide_kmeans,
                 result.wide_descriptors);

  for (const auto& run : options.runs) {
    const auto& classes = run.set == "A" ? result.set_a : result.set_b;
    const features::Vocabulary& v = run.dictionary == "specific" ? *specific : *wide;
    const auto train_idx = images_of(set, split.train, classes);
    const auto test_idx = images_of(set, split.test, classes);
    const LabelledCorpus train_docs =
        relabel(image_corpus(set, train_idx, v, options.features, progress), classes);
    const LabelledCorpus test_docs =
        relabel(image_corpus(set, test_idx, v, options.features, progress), classes);
    SetRunResult r;
    r.run = run;
    r.train_documents = static_cast<int>(train_docs.corpus.num_documents());
    r.test_documents = static_cast<int>(test_docs.corpus.num_documents());
    const auto t1 = std::chrono::steady_clock::now();
    const topics::LdaModel model = train(train_docs.corpus, run.method,
                                         static_cast<int>(classes.size()), options, r.lda_summary);
    r.train_seconds = seconds_since(t1);
    // Topics are named from the labelled training images (never the test labels).
    r.evaluation = evaluate_model(model, train_docs, test_docs);
    result.runs.push_back(std::move(r));
  }
  result.seconds = seconds_since(t0);
  return result;
}

void ScatterExperimentOptions::validate() const {
  if (topics.empty()) throw Error("no numbers of topics given");
  for (int k : topics)
    if (k < 0) throw Error("the number of topics K must be >= 1 (0 = the number of objects)");
  frames.validate();
  if (frame_step < 1) throw Error("the frame step must be >= 1");
  if (dictionary_frames < 1 || descriptors_per_frame < 1) {
    throw Error("the dictionary needs at least 1 frame and 1 descriptor per frame");
  }
  kmeans.validate();
  topics::OnlineLdaOptions on = online;
  on.num_topics = 1;
  on.validate();
  if (mot) mot_options.validate();
  if (!(mapping_fraction > 0 && mapping_fraction < 1)) {
    throw Error("the fraction of views used to name topics must be in (0, 1)");
  }
  view_features.validate();
  if (view_dilate < 0 || view_dilate > 100) {
    throw Error("the views' mask growth must be in [0, 100] pixels");
  }
  check_mask_change(view_dilate, view_erode);
  check_erode_min_features(view_erode_min_features);
  if (mot_grid_components.empty()) throw Error("the MoT grid needs at least one component cap");
  for (const int c : mot_grid_components) {
    if (c < 2 || c > 1000) throw Error("the MoT grid's component caps must be in [2, 1000]");
  }
  for (const double w : mot_grid_word_weights) {
    if (!(w >= 0 && w <= 1)) throw Error("the MoT grid's word weights must be in [0, 1]");
  }
}

namespace {

// The labelled views that name the topics and the test views, over the vocabulary, for the
// options' seed.
using ViewCorpora = std::function<std::pair<LabelledCorpus, LabelledCorpus>(
    const features::Vocabulary&, const ScatterExperimentOptions&, ScatterExperimentResult&)>;

// One result per seed: the frames' features are extracted once; each seed then builds its
// dictionary, documents and models exactly as a run with that seed alone.
std::vector<ScatterExperimentResult> run_scatter(
    const std::vector<episode::Episode>& episodes, const std::vector<std::string>& objects,
    const ScatterExperimentOptions& options, const std::vector<std::uint64_t>& seeds,
    const features::Vocabulary* vocabulary, const ProgressFn& progress,
    const ViewCorpora& make_views, const ScatterSeedDoneFn& seed_done = {}) {
  options.validate();
  if (episodes.empty()) throw Error("no episodes given");
  if (seeds.empty()) throw Error("no seeds given");
  const auto t0 = std::chrono::steady_clock::now();
  FrameDocumentOptions frame_options = options.frames;
  const bool by_objects = frame_options.region == FrameRegion::kObjects ||
                          frame_options.region == FrameRegion::kEachObject;
  if (by_objects && frame_options.objects.empty()) frame_options.objects = objects;
  for (const auto& e : episodes) {
    if (by_objects && selected_object_ids(e, frame_options.objects).empty()) {
      std::string m = "none of the objects ";
      m += join(frame_options.objects);
      m += " is in this episode";
      throw Error::in_file(e.dir(), m);
    }
  }

  // Features of every used frame, in the order the robot saw them.
  std::vector<features::Features> docs;
  int frames = 0;
  std::size_t total = 0;
  for (const auto& e : episodes)
    total +=
        static_cast<std::size_t>((e.frame_count() + options.frame_step - 1) / options.frame_step);
  std::size_t done = 0;
  for (const auto& e : episodes) {
    for (int i = 0; i < e.frame_count(); i += options.frame_step) {
      for (auto& f : frame_features(e, i, frame_options))
        if (!f.empty()) docs.push_back(std::move(f));
      ++frames;
      if (progress) progress(++done, total);
    }
  }
  if (docs.empty()) throw Error("the episodes' frames have no features in the chosen region");
  const double extraction_seconds = seconds_since(t0);

  std::vector<ScatterExperimentResult> results;
  for (const std::uint64_t seed : seeds) {
    const auto t1 = std::chrono::steady_clock::now();
    ScatterExperimentOptions o = options;
    o.seed = seed;
    ScatterExperimentResult result;
    result.objects = objects;
    result.frames = frames;
    std::optional<features::Vocabulary> built;
    const features::Vocabulary* v = vocabulary;
    if (v == nullptr) {
      core::Rng rng(o.seed);
      std::vector<std::size_t> order(docs.size());
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::shuffle(order.begin(), order.end(), rng.engine());
      order.resize(std::min(order.size(), static_cast<std::size_t>(o.dictionary_frames)));
      cv::Mat sample(0, features::kDescriptorLength, CV_32F);
      for (std::size_t d : order) {
        const auto& f = docs[d];
        std::vector<int> rows(static_cast<std::size_t>(f.size()));
        std::iota(rows.begin(), rows.end(), 0);
        std::shuffle(rows.begin(), rows.end(), rng.engine());
        rows.resize(std::min(rows.size(), static_cast<std::size_t>(o.descriptors_per_frame)));
        for (int r : rows) sample.push_back(f.descriptors.row(r));
      }
      features::KmeansOptions k = o.kmeans;
      k.seed = o.seed;
      if (k.words > sample.rows) {
        std::string m = "the frames give fewer descriptors (";
        m += std::to_string(sample.rows);
        m += ") than the dictionary's words";
        throw Error(m);
      }
      auto r = features::build_vocabulary(sample, k);
      result.kmeans = r.summary;
      result.dictionary_descriptors = sample.rows;
      built = std::move(r.vocabulary);
      v = &*built;
    }
    result.words = v->size();
    if (v->dimension() != features::kDescriptorLength) {
      throw Error("the vocabulary's words are not 128-D SIFT descriptors");
    }

    topics::Corpus corpus(v->size());
    for (const auto& f : docs) corpus.add_tokens(features::bag_of_words(*v, f.descriptors));
    result.documents = static_cast<int>(corpus.num_documents());
    result.tokens = corpus.num_tokens();

    const auto [mapping_docs, test_docs] = make_views(*v, o, result);
    for (int k : o.topics) {
      topics::OnlineLdaOptions on = o.online;
      on.num_topics = k == 0 ? static_cast<int>(objects.size()) : k;
      on.seed = o.seed;
      // batch_size counts frames: with several documents a frame (blobs, each-object) a
      // mini-batch holds the documents of that many frames on average.
      on.batch_size = std::max(
          1, static_cast<int>(std::lround(o.online.batch_size *
                                          static_cast<double>(result.documents) / result.frames)));
      result.batch_documents = on.batch_size;
      auto trained = topics::train_online_lda(corpus, on);
      ScatterRunResult r;
      r.topics = on.num_topics;
      r.summary = trained.summary;
      r.evaluation = evaluate_model(trained.model, mapping_docs, test_docs);
      if (o.mot) {
        r.mot = evaluate_mot(trained.model, mapping_docs, test_docs, o.mot_options);
        r.mot_unsupervised =
            evaluate_mot_unsupervised(trained.model, mapping_docs, test_docs, o.mot_options);
        // The objects' word multinomials from the labelled views (for mot_grid_word_weights).
        const Eigen::MatrixXd log_phi =
            o.mot_grid_word_weights.empty()
                ? Eigen::MatrixXd()
                : topics::fit_word_multinomials(mapping_docs.corpus, mapping_docs.labels,
                                                static_cast<int>(mapping_docs.classes.size()));
        for (const auto source : {ThetaSource::kEStep, ThetaSource::kWordPosterior}) {
          for (const double s : o.mot_smoothing_grid) {
            for (const auto prior : {topics::MotPrior::kViews, topics::MotPrior::kUniform}) {
              // The mixture once per component cap.
              std::vector<std::pair<std::string, int>> models{{"dirichlet", 1},
                                                              {"shared-precision", 1}};
              for (const int c : o.mot_grid_components) models.emplace_back("mixture", c);
              for (const auto& [model, components] : models) {
                topics::MotOptions g = o.mot_options;
                g.smoothing = s;
                g.prior = prior;
                g.shared_precision = model == "shared-precision";
                g.components = components;
                const MotEvaluation e =
                    evaluate_mot(trained.model, mapping_docs, test_docs, g, {}, source);
                r.mot_grid.push_back(
                    {source, s, prior, model, components, std::nullopt, e.classes});
                // The same objects' Dirichlets classifying the test views by their words
                // (topics::classify_mot_words): smoothing does not enter, so once per source
                // and object model, with the prior from the views.
                if (s == o.mot_smoothing_grid.front() && prior == topics::MotPrior::kViews) {
                  const topics::MotClassification w =
                      topics::classify_mot_words(e.fit.model, trained.model, test_docs.corpus);
                  std::vector<int> predicted = w.predicted;
                  for (std::size_t d = 0; d < predicted.size(); ++d)
                    if (test_docs.corpus.document(d).empty()) predicted[d] = -1;
                  if (source == ThetaSource::kEStep && model == "mixture" &&
                      components == o.mot_grid_components.front())
                    r.mixture_words_predicted = predicted;
                  r.mot_grid.push_back({source, 0, prior, model + "-words", components,
                                        std::nullopt,
                                        confusion_matrix(test_docs.labels, predicted,
                                                         test_docs.classes, test_docs.classes)});
                  for (const double weight : o.mot_grid_word_weights) {
                    std::vector<int> pooled = topics::pool_word_multinomials(
                                                  e.fit.model, w, log_phi, test_docs.corpus, weight)
                                                  .predicted;
                    for (std::size_t d = 0; d < pooled.size(); ++d)
                      if (test_docs.corpus.document(d).empty()) pooled[d] = -1;
                    r.mot_grid.push_back({source, 0, prior, model + "-words-multinomial",
                                          components, weight,
                                          confusion_matrix(test_docs.labels, pooled,
                                                           test_docs.classes, test_docs.classes)});
                  }
                }
              }
            }
          }
        }
        if (!o.mot_smoothing_grid.empty())
          r.ceilings = representation_ceilings(trained.model, mapping_docs, test_docs);
      }
      result.runs.push_back(std::move(r));
    }
    // The frames' feature extraction (shared by the seeds) and this seed's own work.
    result.seconds = extraction_seconds + seconds_since(t1);
    results.push_back(std::move(result));
    if (seed_done) seed_done(results.size() - 1, results.back());
  }
  return results;
}

}  // namespace

ScatterExperimentResult run_scatter_experiment(const std::vector<episode::Episode>& episodes,
                                               const features::ImageSet& views,
                                               const ScatterExperimentOptions& options,
                                               const features::Vocabulary* vocabulary,
                                               const ProgressFn& progress) {
  auto make_views = [&](const features::Vocabulary& v, const ScatterExperimentOptions& o,
                        ScatterExperimentResult& result) {
    // Views: per class, a random mapping_fraction names the topics, the rest is the test.
    std::vector<std::size_t> all(views.images.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    std::vector<std::size_t> mapping_idx, test_idx;
    {
      auto rng = core::Rng::stream(o.seed, 7);
      std::vector<std::vector<std::size_t>> per_class(views.classes.size());
      for (std::size_t i : all) per_class[static_cast<std::size_t>(views.labels[i])].push_back(i);
      for (std::size_t c = 0; c < per_class.size(); ++c) {
        auto members = per_class[c];
        if (members.size() < 2) {
          std::string m = "class '";
          m += views.classes[c];
          m += "' needs at least 2 views (to name topics and to test)";
          throw Error(m);
        }
        std::shuffle(members.begin(), members.end(), rng.engine());
        auto n = static_cast<std::size_t>(
            std::lround(options.mapping_fraction * static_cast<double>(members.size())));
        n = std::clamp<std::size_t>(n, 1, members.size() - 1);
        mapping_idx.insert(mapping_idx.end(), members.begin(),
                           members.begin() + static_cast<long>(n));
        test_idx.insert(test_idx.end(), members.begin() + static_cast<long>(n), members.end());
      }
      std::sort(mapping_idx.begin(), mapping_idx.end());
      std::sort(test_idx.begin(), test_idx.end());
    }
    LabelledCorpus mapping_docs = image_corpus(views, mapping_idx, v, options.view_features);
    LabelledCorpus test_docs = image_corpus(views, test_idx, v, options.view_features);
    result.mapping_views = static_cast<int>(mapping_idx.size());
    result.test_views = static_cast<int>(test_idx.size());
    return std::pair(std::move(mapping_docs), std::move(test_docs));
  };
  return run_scatter(episodes, views.classes, options, {options.seed}, vocabulary, progress,
                     make_views)
      .front();
}

std::vector<ScatterExperimentResult> run_scatter_experiments(
    const std::vector<episode::Episode>& episodes,
    const std::vector<episode::Episode>& view_episodes, const std::vector<std::string>& objects,
    const ScatterExperimentOptions& options, const std::vector<std::uint64_t>& seeds,
    const features::Vocabulary* vocabulary, const ProgressFn& progress,
    const ScatterSeedDoneFn& seed_done) {
  if (view_episodes.empty()) throw Error("no view episodes given");
  if (objects.empty()) throw Error("no objects named for the views");
  if (options.view_step < 1 || options.view_min_features < 1 || options.view_block < 1) {
    throw Error("the view step, block and least features of a view must be >= 1");
  }
  // The views' features do not depend on the seed: extracted at the first seed, quantized by
  // each seed's vocabulary.
  std::optional<std::pair<LabelledFeatures, LabelledFeatures>> view_features;
  auto make_views = [&](const features::Vocabulary& v, const ScatterExperimentOptions& /*o*/,
                        ScatterExperimentResult& result) {
    // Blocks of view_block frames go to the mapping side when the running share of mapping
    // blocks falls behind mapping_fraction, so both sides see every episode (whichever object
    // is pushed near the camera there) while near-identical neighbouring frames mostly stay on
    // one side.
    std::vector<std::vector<int>> mapping_frames, test_frames;
    for (const auto& e : view_episodes) {
      mapping_frames.emplace_back();
      test_frames.emplace_back();
      for (int i = 0; i < e.frame_count(); i += options.view_step) {
        const int b = i / options.view_block;
        const bool mapping = options.split_by_episode
                                 ? static_cast<double>(mapping_frames.size()) <=
                                       std::round(options.mapping_fraction *
                                                  static_cast<double>(view_episodes.size()))
                                 : std::floor((b + 1) * options.mapping_fraction) >
                                       std::floor(b * options.mapping_fraction);
        (mapping ? mapping_frames : test_frames).back().push_back(i);
      }
    }
    auto features_of = [&](const std::vector<std::vector<int>>& frames, const char* side) {
      LabelledFeatures c =
          object_view_features(view_episodes, frames, objects, options.view_features,
                               options.view_min_features, options.view_dilate, options.view_erode,
                               options.view_selection, options.view_erode_min_features);
      for (int k = 0; k < static_cast<int>(objects.size()); ++k) {
        if (std::find(c.labels.begin(), c.labels.end(), k) == c.labels.end()) {
          std::string m = "object '";
          m += objects[static_cast<std::size_t>(k)];
          m += "' has no ";
          m += side;
          m += " view with enough features in the view episodes (";
          m += view_episodes.front().dir().string();
          m += "...)";
          throw Error(m);
        }
      }
      return c;
    };
    if (!view_features) {
      // In this order (an argument list's is unspecified): the labelled side's error first.
      LabelledFeatures mapping = features_of(mapping_frames, "labelled");
      LabelledFeatures test = features_of(test_frames, "test");
      view_features.emplace(std::move(mapping), std::move(test));
    }
    LabelledCorpus mapping_docs = views_corpus(view_features->first, v);
    LabelledCorpus test_docs = views_corpus(view_features->second, v);
    result.mapping_views = static_cast<int>(mapping_docs.labels.size());
    result.test_views = static_cast<int>(test_docs.labels.size());
    result.test_origins = view_features->second.origins;
    result.test_labels = view_features->second.labels;
    result.test_features.clear();
    for (const features::Features& f : view_features->second.views)
      result.test_features.push_back(f.size());
    return std::pair(std::move(mapping_docs), std::move(test_docs));
  };
  return run_scatter(episodes, objects, options, seeds, vocabulary, progress, make_views,
                     seed_done);
}

ScatterExperimentResult run_scatter_experiment(const std::vector<episode::Episode>& episodes,
                                               const std::vector<episode::Episode>& view_episodes,
                                               const std::vector<std::string>& objects,
                                               const ScatterExperimentOptions& options,
                                               const features::Vocabulary* vocabulary,
                                               const ProgressFn& progress) {
  return run_scatter_experiments(episodes, view_episodes, objects, options, {options.seed},
                                 vocabulary, progress)
      .front();
}

}  // namespace proprio::recognition
