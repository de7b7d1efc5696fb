#include "proprio/recognition/experiment_runs.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>

#include "proprio/core/error.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/recognize_runs.hpp"
#include "run_support.hpp"

namespace proprio::recognition {
namespace {

using detail::progress_bar;
using detail::read_episodes;

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) {
    if (!s.empty()) s += ',';
    s += x;
  }
  return s;
}

std::vector<std::string> strings(const std::vector<std::filesystem::path>& paths) {
  std::vector<std::string> out(paths.size());
  std::transform(paths.begin(), paths.end(), out.begin(),
                 [](const std::filesystem::path& p) { return p.string(); });
  return out;
}

std::optional<KmeansRecord> kmeans_record(const std::optional<features::KmeansSummary>& s,
                                          int descriptors) {
  if (!s) return std::nullopt;
  return KmeansRecord::of(*s, descriptors);
}

}  // namespace

KmeansRecord KmeansRecord::of(const features::KmeansSummary& s, int descriptors) {
  return {descriptors, s.iterations, s.cost, s.seconds, s.termination};
}

ExperimentRun run_set_experiment_files(const SetExperimentRunOptions& options,
                                       const core::Provenance& provenance) {
  SetExperimentOptions o = options.options;
  if (o.runs.empty()) o.runs = options.dictionary ? dictionary_runs() : batch_online_runs();
  o.batch.seed = o.seed;
  o.online.seed = o.seed;
  o.kmeans.seed = o.seed;
  const features::ImageSet set = features::read_image_set(options.images);
  std::shared_ptr<core::ProgressBar> bar;
  const SetExperimentResult r =
      run_set_experiment(set, o, progress_bar(bar, "images", options.progress));
  ExperimentRun out;
  out.report =
      core::printf_string("set A: %s\nset B: %s\nwide dictionary: %s\n\n", joined(r.set_a).c_str(),
                          joined(r.set_b).c_str(), joined(r.wide).c_str());
  SetExperimentRecord& rec = out.set.emplace();
  rec.images = options.images;
  rec.set_a = r.set_a;
  rec.set_b = r.set_b;
  rec.wide = r.wide;
  rec.words = o.kmeans.words;
  rec.test_per_class = o.test_per_class;
  rec.features = features::to_string(o.features.kind);
  rec.specific_dictionary = kmeans_record(r.specific_kmeans, r.specific_descriptors);
  rec.wide_dictionary = kmeans_record(r.wide_kmeans, r.wide_descriptors);
  for (const SetRunResult& run : r.runs) {
    const std::string title = run.run.name + " (set " + run.run.set + ", " + run.run.dictionary +
                              " dictionary, " + to_string(run.run.method) + " LDA)";
    out.report += evaluation_report(title, run.evaluation);
    rec.runs.push_back({run.evaluation, run.run.name, run.run.set, run.run.dictionary,
                        std::string(to_string(run.run.method)), run.train_documents,
                        run.test_documents, run.train_seconds, run.lda_summary});
  }
  out.report += core::printf_string("seconds: %.1f\n", r.seconds);
  rec.seconds = r.seconds;
  out.document = core::result_document(
      options.dictionary ? "proprio.experiment.dictionary" : "proprio.experiment.batch_online", 1,
      provenance);
  core::fields_into_json(rec, out.document);
  out.message = core::first_line(out.brief());
  return out;
}

void ScatterExperimentRunOptions::validate() const {
  if (views.empty() == view_episodes.empty()) {
    throw Error("give either --views DIR or --view-episodes DIR... (with --objects)");
  }
  if (!view_episodes.empty() && objects.empty()) {
    throw Error("--view-episodes needs --objects (the objects whose views are cut from them)");
  }
}

namespace {

ExperimentRun scatter_run(const ScatterExperimentRunOptions& options,
                          const ScatterExperimentOptions& o, std::size_t episode_count,
                          const ScatterExperimentResult& r, const core::Provenance& provenance) {
  ExperimentRun out;
  out.report =
      core::printf_string(
          "objects: %zu, episodes: %zu, frames: %d, documents: %d, tokens: %lld, words: %d\n",
          r.objects.size(), episode_count, r.frames, r.documents, static_cast<long long>(r.tokens),
          r.words) +
      core::printf_string("mini-batches: %d documents (%d frames)\n", r.batch_documents,
                          o.online.batch_size) +
      core::printf_string("views: %d name the topics (labelled), %d test\n\n", r.mapping_views,
                          r.test_views);
  ScatterExperimentRecord& rec = out.scatter.emplace();
  rec.episodes = strings(options.episodes);
  if (!options.views.empty()) rec.views = options.views.string();
  if (!options.view_episodes.empty()) {
    rec.view_episodes = strings(options.view_episodes);
    rec.view_step = o.view_step;
    rec.view_block = o.view_block;
    rec.mask_dilate = o.view_dilate;
    rec.mask_erode = o.view_erode;
    rec.mask_erode_min_features = o.view_erode_min_features;
    rec.view_selection = o.view_selection == ViewSelection::kBareMask ? "bare" : "mask";
    rec.view_split = o.split_by_episode ? "episodes" : "blocks";
  }
  rec.mot = o.mot;
  rec.objects = r.objects;
  rec.region = to_string(o.frames.region);
  rec.features = features::to_string(o.frames.features.kind);
  rec.frames = r.frames;
  rec.documents = r.documents;
  rec.tokens = r.tokens;
  rec.words = r.words;
  rec.batch_size = o.online.batch_size;
  rec.batch_documents = r.batch_documents;
  rec.passes = o.online.passes;
  rec.mapping_views = r.mapping_views;
  rec.test_views = r.test_views;
  if (!r.test_origins.empty()) {
    std::vector<ScatterViewRecord>& views = rec.test_view_origins.emplace();
    for (std::size_t i = 0; i < r.test_origins.size(); ++i) {
      const ViewOrigin& v = r.test_origins[i];
      views.push_back({v.episode, v.frame, r.objects[static_cast<std::size_t>(r.test_labels[i])],
                       r.test_features[i], v.mask_pixels, v.at_border});
    }
  }
  rec.dictionary = kmeans_record(r.kmeans, r.dictionary_descriptors);
  for (const ScatterRunResult& run : r.runs) {
    const std::string title = "K = " + std::to_string(run.topics);
    out.report += evaluation_report(title, run.evaluation);
    ScatterRunRecord& j = rec.runs.emplace_back();
    j.evaluation = run.evaluation;
    j.topics_k = run.topics;
    j.updates = run.summary.updates;
    j.train_seconds = run.summary.seconds;
    if (run.mot) {
      out.report += core::printf_string(
          "%s: Mixture of Topics (supervised, thesis 7.1; rows: true object)\n%s", title.c_str(),
          run.mot->classes.format().c_str());
      out.report += core::printf_string(
          "%s: Mixture of Topics accuracy %.1f%%, mean class accuracy %.1f%%\n\n", title.c_str(),
          100 * run.mot->classes.accuracy(), 100 * run.mot->classes.mean_class_accuracy());
      ScatterMotRecord& m = j.mot.emplace();
      m.classes = run.mot->classes;
      m.summary = run.mot->fit.summary.brief();
      m.smoothing = run.mot->fit.model.smoothing;
      m.objects = MotObjectRecord::of(run.mot->fit.model);
      for (MotObjectRecord& obj : m.objects) obj.mean.reset();
    }
    if (run.mot_unsupervised) {
      const MotUnsupervisedEvaluation& u = *run.mot_unsupervised;
      out.report += core::printf_string(
          "%s: Mixture of Topics, unsupervised (k-means over theta, C = %zu; objects named "
          "by the labelled views; BIC would choose C = %d)\n%s",
          title.c_str(), r.objects.size(), u.chosen_classes, u.classes.format().c_str());
      out.report += core::printf_string(
          "%s: unsupervised Mixture of Topics accuracy %.1f%%, mean class accuracy %.1f%%\n\n",
          title.c_str(), 100 * u.classes.accuracy(), 100 * u.classes.mean_class_accuracy());
      j.mot_unsupervised = ScatterUnsupervisedRecord{u.classes, u.chosen_classes, u.object_class,
                                                     u.chosen_per_class};
    }
    if (!run.mot_grid.empty()) {
      std::vector<ScatterGridRecord>& grid = j.mot_grid.emplace();
      for (const MotGridPoint& g : run.mot_grid) {
        ScatterGridRecord& point = grid.emplace_back(
            ScatterGridRecord{g.classes, g.source, g.smoothing,
                              g.prior == topics::MotPrior::kUniform ? "uniform" : "views", g.model,
                              std::nullopt, g.word_weight});
        if (g.model.starts_with("mixture")) point.components = g.components;
      }
    }
    if (!run.mixture_words_predicted.empty())
      j.mixture_words_predicted = run.mixture_words_predicted;
    if (!run.ceilings.empty()) {
      std::vector<ScatterCeilingRecord>& c = j.ceilings.emplace();
      for (const RepresentationCeiling& x : run.ceilings) {
        c.push_back({x.classes, x.name});
        out.report +=
            core::printf_string("%s: ceiling %s: mean class accuracy %.1f%%\n", title.c_str(),
                                x.name.c_str(), 100 * x.classes.mean_class_accuracy());
      }
    }
  }
  out.report += core::printf_string("seconds: %.1f\n", r.seconds);
  rec.seconds = r.seconds;
  out.document = core::result_document("proprio.experiment.scatter", 1, provenance);
  core::fields_into_json(rec, out.document);
  out.message = core::first_line(out.brief());
  return out;
}

}  // namespace

std::vector<ExperimentRun> run_scatter_experiments_files(const ScatterExperimentRunOptions& options,
                                                         const core::Provenance& provenance,
                                                         const ScatterRunDoneFn& run_done) {
  options.validate();
  ScatterExperimentOptions o = options.options;
  o.view_features = o.frames.features;
  o.frames.features.center_crop = 1.0;  // frames: the region decides
  o.kmeans.seed = o.seed;
  const std::vector<std::uint64_t> seeds =
      options.seeds.empty() ? std::vector<std::uint64_t>{o.seed} : options.seeds;
  if (seeds.size() > 1 && !options.views.empty()) {
    throw Error("several seeds at once need --view-episodes (not --views)");
  }
  const std::vector<episode::Episode> episodes = read_episodes(options.episodes);
  std::optional<features::Vocabulary> vocabulary;
  if (!options.vocabulary.empty()) vocabulary = features::read_vocabulary(options.vocabulary);
  const features::Vocabulary* v = vocabulary ? &*vocabulary : nullptr;
  std::shared_ptr<core::ProgressBar> bar;
  // Each seed's run is made (and handed to run_done) as soon as that seed is finished.
  std::vector<ExperimentRun> out;
  auto done = [&](std::size_t i, const ScatterExperimentResult& result) {
    core::Provenance p = provenance;
    p.seed = seeds[i];
    ScatterExperimentOptions oi = o;
    oi.seed = seeds[i];
    out.push_back(scatter_run(options, oi, episodes.size(), result, p));
    if (run_done) run_done(i, out.back());
  };
  if (options.views.empty()) {
    // Segmented views: the features inside each object's mask; no centre crop.
    o.view_features.center_crop = 1.0;
    (void)run_scatter_experiments(episodes, read_episodes(options.view_episodes), options.objects,
                                  o, seeds, v, progress_bar(bar, "frames", options.progress), done);
  } else {
    const features::ImageSet views = features::read_image_set(options.views);
    o.seed = seeds.front();
    o.kmeans.seed = o.seed;
    done(0, run_scatter_experiment(episodes, views, o, v,
                                   progress_bar(bar, "frames", options.progress)));
  }
  return out;
}

ExperimentRun run_scatter_experiment_files(const ScatterExperimentRunOptions& options,
                                           const core::Provenance& provenance) {
  ScatterExperimentRunOptions one = options;
  one.seeds.clear();
  return run_scatter_experiments_files(one, provenance).front();
}

}  // namespace proprio::recognition
