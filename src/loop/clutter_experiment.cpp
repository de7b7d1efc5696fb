#include "proprio/loop/clutter_experiment.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <span>

#include "arm_image.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/mask_morphology.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/loop/clutter_cache.hpp"
#include "proprio/loop/push_run.hpp"
#include "proprio/loop/self_supervision.hpp"
#include "proprio/loop/self_supervision_scoring.hpp"
#include "proprio/loop/view_model.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/corpus.hpp"

namespace proprio::loop {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::uint64_t kTrialStream = 0x7c1a;
constexpr std::uint64_t kTargetStream = 0x7c1b;
constexpr int kMaxReplacements = 3;  // re-placements of the scene when the object is not seen
constexpr std::string_view kCacheMarkers[] = {"clutter_cache.json"};

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::vector<std::string> names_of(const std::string& list) {
  if (list.empty()) return {};
  return parse_object_list(list);
}

// What a cached directory's manifest must say for this experiment (the options that shape
// the recording).
core::Json recording_key(const ClutterExperimentOptions& o, std::uint64_t seed) {
  core::Json k{{"objects", o.objects},       {"clutter", o.clutter},
               {"background", o.background}, {"seed", seed},
               {"pushes", o.pushes},         {"fps", o.fps},
               {"width", o.width},           {"height", o.height},
               {"held_out", o.held_out},     {"min_shift", o.min_shift},
               {"max_shift", o.max_shift}};
  // Session 22's harness options, only when not the session-21 harness (whose caches stay
  // valid for --attempts 1).
  if (o.attempts != 1) k["attempts"] = o.attempts;
  if (o.sweep_margin != 0) k["sweep_margin"] = o.sweep_margin;
  if (o.depth_split != 0) k["depth_split"] = o.depth_split;
  return k;
}

// Reads a cached directory's manifest: nullopt when the directory does not exist; Error when
// it is not this experiment's cache or was recorded with other options (unless overwrite: then
// nullopt, to record again).
std::optional<core::Json> read_cache(const fs::path& dir, const core::Json& key, bool overwrite) {
  if (!fs::exists(dir)) return std::nullopt;
  const fs::path file = dir / "clutter_cache.json";
  if (!fs::exists(file)) {
    throw Error(dir.string() +
                ": not a cache of proprio experiment clutter (no clutter_cache.json)");
  }
  const core::Json j = core::read_json(file);
  const ClutterManifestMatch match = match_clutter_manifest(j, key);
  if (match == ClutterManifestMatch::kOtherFormat) {
    if (overwrite) return std::nullopt;
    throw Error(file.string() + ": not a " + kClutterCacheFormat + " version " +
                std::to_string(kClutterCacheVersion) +
                " manifest (use --overwrite to record again)");
  }
  if (match == ClutterManifestMatch::kOtherOptions) {
    if (overwrite) return std::nullopt;
    throw Error(file.string() +
                ": recorded with other options (use --overwrite to record again, or another "
                "--cache)");
  }
  return j;
}

Eigen::Vector2d push_target(const sim::ObjectTruth& t, const ClutterExperimentOptions& o,
                            core::Rng& rng) {
  const sim::ScatterRegion region;
  const Eigen::Vector2d c = t.centre.head<2>();
  for (int attempt = 0; attempt < 200; ++attempt) {
    const double a = rng.uniform(0.0, 2 * std::numbers::pi);
    const double r = rng.uniform(o.min_shift, o.max_shift);
    Eigen::Vector2d p = c + r * Eigen::Vector2d(std::cos(a), std::sin(a));
    const double margin = 0.04;
    if (p.x() < region.min.x() + margin || p.x() > region.max.x() - margin ||
        p.y() < region.min.y() + margin || p.y() > region.max.y() - margin) {
      continue;
    }
    if (p.norm() > region.max_radius - 0.04 || p.norm() < 0.18) continue;
    return p;
  }
  // No point fits: toward the scatter region's middle.
  const Eigen::Vector2d mid(0.27, 0.0);
  const Eigen::Vector2d d = mid - c;
  return d.norm() < 1e-6 ? mid : Eigen::Vector2d(c + d.normalized() * o.min_shift);
}

// One trial: scatter, `pushes` pushes of `object`, each planned by push_once; committed whole.
void record_trial(sim::SimulatedRobot& robot, const ClutterExperimentOptions& o, std::uint64_t seed,
                  std::size_t oi, const std::string& object, int trial, const fs::path& dir,
                  const core::Provenance& provenance) {
  core::StagedDirectory staged(dir, o.overwrite, kCacheMarkers);
  const fs::path work = staged.staging_path();
  robot.scatter(core::stream_seed(seed, kTrialStream, oi, static_cast<std::uint64_t>(trial)));
  core::Rng rng(core::stream_seed(seed, kTargetStream, oi, static_cast<std::uint64_t>(trial)));
  core::Json pushes = core::Json::array();
  const auto find_object = [&]() -> std::optional<sim::ObjectTruth> {
    for (const auto& t : robot.ground_truth()) {
      if (t.name == object) return t;
    }
    return std::nullopt;
  };
  for (int k = 0; k < o.pushes; ++k) {
    PushOptions po;
    po.table = {};  // the robot's table
    po.object = object;
    po.fps = o.fps;
    po.max_pushes = 1;
    // The planner's pixel quantities scaled with the image, as learn scales them.
    const double scale = o.width / 640.0;
    po.plan.grid_step = std::max(2, static_cast<int>(std::lround(po.plan.grid_step * scale)));
    po.plan.patch = std::max(4, static_cast<int>(std::lround(po.plan.patch * scale)));
    po.plan.blobs.sigma = po.plan.blobs.sigma * scale;
    po.plan.sweep_margin = o.sweep_margin;
    po.plan.depth_split = o.depth_split;
    // The experiment's pushes aim where it asks (recorded so; loop::kLoopFreeTargetMargin, the
    // push loop's default since session 28, was not measured here).
    po.plan.free_target_margin = 0;
    // Nor loop::kLoopTallStartClearance (session 32's default of the push loop).
    po.plan.tall_start_clearance = 0;
    char name[32];
    std::snprintf(name, sizeof name, "push_%02d", k);
    po.out = work / name;
    core::Json pj{{"index", k}};
    const auto rescatter = [&](int n) {
      robot.scatter(core::stream_seed(seed, kTrialStream, oi, static_cast<std::uint64_t>(trial),
                                      static_cast<std::uint64_t>(k),
                                      static_cast<std::uint64_t>(n)));
    };
    if (o.attempts > 1) {
      // Session 22: up to `attempts` attempts, re-placing the scene when the object is not free.
      int replaced = 0;
      core::Json failed = core::Json::array();
      std::optional<PushRunResult> r;
      int attempt = 0;
      for (; attempt < o.attempts; ++attempt) {
        const std::optional<sim::ObjectTruth> t = find_object();
        if (!t || !t->on_table) {
          failed.push_back("off-table");
          rescatter(++replaced);
          continue;
        }
        const Eigen::Vector2d target = push_target(*t, o, rng);
        po.target_x = target.x();
        po.target_y = target.y();
        fs::remove_all(po.out);
        r = push_once(robot, po, provenance);
        if (r->report.has_value() && !r->report->episode_dir.empty()) break;
        failed.push_back(std::string(core::choice_name(r->outcome, kPushOutcomeNames)));
        if (r->outcome == PushOutcome::kObjectNotSeen || attempt % 2 == 1) rescatter(++replaced);
      }
      const bool executed =
          r && r->report.has_value() && !r->report->episode_dir.empty() && attempt < o.attempts;
      if (!executed) fs::remove_all(po.out);
      pj["replaced"] = replaced;
      pj["attempts"] = std::min(attempt + 1, o.attempts);
      pj["failed"] = failed;
      pj["outcome"] = r ? std::string(core::choice_name(r->outcome, kPushOutcomeNames))
                        : std::string("off-table");
      if (!executed && !failed.empty()) pj["outcome"] = failed.back();
      pj["episode"] = executed ? std::string(name) + "/episode" : std::string();
      pj["moved_intended"] = executed && r->score.moved_intended;
      pj["only_intended"] = executed && r->score.only_intended;
      pushes.push_back(pj);
      continue;
    }
    const std::optional<sim::ObjectTruth> it = find_object();
    if (!it || !it->on_table) {
      pj["outcome"] = "off-table";
      pj["episode"] = "";
      pj["moved_intended"] = false;
      pj["only_intended"] = false;
      pushes.push_back(pj);
      continue;
    }
    const Eigen::Vector2d target = push_target(*it, o, rng);
    po.target_x = target.x();
    po.target_y = target.y();
    PushRunResult r = push_once(robot, po, provenance);
    // The object is not seen as a putative object of its own (merged with a neighbour, or out
    // of view): the experimenter re-places the scene and the push is planned again.
    int replaced = 0;
    while (r.outcome == PushOutcome::kObjectNotSeen && replaced < kMaxReplacements) {
      ++replaced;
      rescatter(replaced);
      const std::optional<sim::ObjectTruth> at = find_object();
      if (!at) break;
      const Eigen::Vector2d again = push_target(*at, o, rng);
      po.target_x = again.x();
      po.target_y = again.y();
      fs::remove_all(po.out);
      r = push_once(robot, po, provenance);
    }
    pj["replaced"] = replaced;
    const bool executed = r.report.has_value() && !r.report->episode_dir.empty();
    pj["outcome"] = std::string(core::choice_name(r.outcome, kPushOutcomeNames));
    pj["episode"] = executed ? std::string(name) + "/episode" : std::string();
    pj["moved_intended"] = r.score.moved_intended;
    pj["only_intended"] = r.score.only_intended;
    pushes.push_back(pj);
  }
  core::Json m = core::result_document(kClutterCacheFormat, kClutterCacheVersion, provenance);
  m["recording"] = recording_key(o, seed);
  m["object"] = object;
  m["trial"] = trial;
  m["pushes"] = pushes;
  core::write_json_atomic(work / "clutter_cache.json", m);
  staged.commit();
}

// Held-out renders of each object alone (as score_self_supervision): image and mask PNGs.
void record_held_out(const ClutterExperimentOptions& o, std::uint64_t seed,
                     const std::vector<std::string>& objects, const fs::path& dir,
                     const core::Provenance& provenance) {
  core::StagedDirectory staged(dir, o.overwrite, kCacheMarkers);
  const fs::path work = staged.staging_path();
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  for (const auto& name : objects) {
    sim::TableOptions table;
    table.objects = {name};
    table.seed = seed;
    table.width = o.width;
    table.height = o.height;
    sim::SimulatedRobot alone(table, catalogue);
    const int id = alone.ground_truth().at(0).id;
    fs::create_directories(work / name);
    for (int v = 0; v < o.held_out; ++v) {
      const HeldOutView view = render_held_out_view(alone, name, id, v, o.held_out);
      char file[32];
      std::snprintf(file, sizeof file, "view_%03d.png", v);
      cv::imwrite((work / name / file).string(), view.image);
      std::snprintf(file, sizeof file, "mask_%03d.png", v);
      cv::imwrite((work / name / file).string(), view.mask);
    }
  }
  core::Json m = core::result_document(kClutterCacheFormat, kClutterCacheVersion, provenance);
  m["recording"] = recording_key(o, seed);
  m["held_out"] = objects;
  core::write_json_atomic(work / "clutter_cache.json", m);
  staged.commit();
}

fs::path trial_dir(const fs::path& cache, std::uint64_t seed, const std::string& object,
                   int trial) {
  return cache / ("seed_" + std::to_string(seed)) / (object + "_t" + std::to_string(trial + 1));
}

// A segmented push's views at every fraction: descriptors per view (CV_32F rows).
using ViewsByFraction = ClutterViews;

ViewsByFraction push_views(const fs::path& episode_dir, const ClutterExperimentOptions& o,
                           const robot::Arm& arm, std::optional<robot::ArmState>& arm_state) {
  const episode::Episode e = episode::read_episode(episode_dir);
  ViewsByFraction out(o.fractions.size());
  const auto arm_mask = [&](int i, cv::Size size) {
    return detail::arm_image_mask(e, i, size, arm, arm_state);
  };
  const auto take = [&](std::size_t fi, int i, const cv::Mat& m0) {
    cv::Mat m = m0.clone();
    m.setTo(0, arm_mask(i, m.size()));
    m = features::eroded(m, o.erode);
    if (cv::countNonZero(m) == 0) return;
    const features::Features f =
        features::extract_features(e.frame(i), o.features, features::dilated(m, o.dilate));
    if (f.size() < o.min_features) return;
    out[fi].push_back(f.descriptors.clone());
  };
  if (o.segmentation == PushSegmentation::kDense) {
    segmentation::MlOptions mo = o.dense;
    mo.mask_fraction = o.fractions.front();
    mo.keep_frame_maps = true;
    const segmentation::MlResult ml = segmentation::segment_ml(e, mo);
    if (ml.scored_frame < 0 || ml.map.empty()) return out;
    double hi = 0;
    cv::minMaxLoc(ml.map, nullptr, &hi);
    if (!(hi > 0)) return out;
    for (std::size_t fi = 0; fi < o.fractions.size(); ++fi) {
      for (int i = ml.scored_frame;
           i < e.frame_count() && i < static_cast<int>(ml.frame_maps.size()); i += o.view_step) {
        const cv::Mat m = ml.frame_maps[static_cast<std::size_t>(i)] >= o.fractions[fi] * hi;
        take(fi, i, m);
      }
    }
    return out;
  }
  // Sparse: segmented again at each fraction (its mask is more than a threshold of the map);
  // pixel quantities scaled with the image as learn scales them.
  const double scale = e.frame(0).cols / 640.0;
  for (std::size_t fi = 0; fi < o.fractions.size(); ++fi) {
    segmentation::SparseOptions so = o.sparse;
    so.mask_fraction = o.fractions[fi];
    so.evidence_step = std::max(3.0, o.sparse.evidence_step * scale);
    so.lambda = o.sparse.lambda * scale * scale;
    so.velocity_bandwidth = o.sparse.velocity_bandwidth * scale;
    so.density_sigma = std::max(2.0, o.sparse.density_sigma * scale);
    const segmentation::MlResult ml = segmentation::segment_ml_sparse(e, so);
    if (ml.scored_frame < 0 || ml.map.empty() || cv::countNonZero(ml.mask) == 0) continue;
    const int touch = ml.scored_frame;
    const auto at_touch = e.ee_image(touch);
    cv::Mat scored = ml.mask.clone();
    scored.setTo(0, arm_mask(touch, scored.size()));
    for (int i = touch; i < e.frame_count(); i += o.view_step) {
      const auto at = e.ee_image(i);
      Eigen::Vector2d d = Eigen::Vector2d::Zero();
      if (at && at_touch) d = *at - *at_touch;
      const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, d.x(), 0, 1, d.y());
      cv::Mat m;
      cv::warpAffine(scored, m, shift, scored.size(), cv::INTER_NEAREST);
      take(fi, i, m);
    }
  }
  return out;
}

// The segmented views of a push are cached beside its episode (views_dense.bin or
// views_sparse.bin; loop/clutter_cache.hpp): the key is the options that shape the views, as
// JSON. Written atomically; a file of another key, version or size is recomputed (and replaced).
std::string views_key(const ClutterExperimentOptions& o) {
  core::Json k{
      {"segmentation", std::string(core::choice_name(o.segmentation, kPushSegmentationNames))},
      {"fractions", o.fractions},
      {"view_step", o.view_step},
      {"min_features", o.min_features},
      {"dilate", o.dilate},
      {"features", core::fields_to_json(o.features)},
      {"dense", core::fields_to_json(o.dense)},
      {"sparse", core::fields_to_json(o.sparse)}};
  if (o.erode != 0) k["erode"] = o.erode;  // only when set: session-21 views stay valid
  return k.dump();
}

fs::path views_file(const fs::path& episode_dir, const ClutterExperimentOptions& o) {
  return episode_dir.parent_path() /
         (std::string("views_") +
          std::string(core::choice_name(o.segmentation, kPushSegmentationNames)) +
          (o.erode != 0 ? "_e" + std::to_string(o.erode) : std::string()) + ".bin");
}

double share(int right, int n) { return n > 0 ? static_cast<double>(right) / n : 0.0; }

struct SeedData {
  std::uint64_t seed = 0;
  // per fraction: views (descriptors) and their object
  std::vector<std::vector<cv::Mat>> views;
  std::vector<std::vector<int>> labels;
  std::vector<std::vector<int>> trials;  // per fraction: each view's trial
  // held-out descriptors per object
  std::vector<std::vector<cv::Mat>> held;
};

// The share of views classified as their label, overall and per label (0 for a label with none).
std::pair<double, std::vector<double>> label_accuracy(const std::vector<int>& labels,
                                                      const std::vector<int>& predicted, int C) {
  std::vector<int> right(static_cast<std::size_t>(C), 0);
  std::vector<int> n(static_cast<std::size_t>(C), 0);
  int all = 0;
  for (std::size_t v = 0; v < labels.size(); ++v) {
    const auto l = static_cast<std::size_t>(labels[v]);
    ++n[l];
    if (predicted[v] == labels[v]) {
      ++right[l];
      ++all;
    }
  }
  std::vector<double> per(static_cast<std::size_t>(C), 0.0);
  for (std::size_t c = 0; c < per.size(); ++c) per[c] = share(right[c], n[c]);
  return {share(all, static_cast<int>(labels.size())), per};
}

// `d`: the seed swept; `all`: every seed's data (the other seeds' push views are its held-out
// pushes).
void sweep_seed(const SeedData& d, const std::vector<SeedData>& all,
                const ClutterExperimentOptions& o, const std::vector<std::string>& objects,
                std::vector<ClutterCell>& cells, core::ProgressBar& bar) {
  const int C = static_cast<int>(objects.size());
  for (std::size_t fi = 0; fi < o.fractions.size(); ++fi) {
    const auto& views = d.views[fi];
    const auto& labels = d.labels[fi];
    std::vector<int> per(static_cast<std::size_t>(C), 0);
    for (int l : labels) ++per[static_cast<std::size_t>(l)];
    std::optional<features::Vocabulary> vocabulary;
    if (!views.empty()) vocabulary = views_vocabulary(views, o.words, d.seed);
    // A document's tokens (ClutterExperimentOptions::right_angle_words: with its descriptors'
    // quarter turns).
    const auto words_of = [&](const cv::Mat& descriptors) {
      return features::bag_of_words(*vocabulary, o.right_angle_words
                                                     ? features::with_right_angle_turns(descriptors)
                                                     : descriptors);
    };
    for (int t : o.topics) {
      ClutterCell cell;
      cell.seed = d.seed;
      cell.fraction = o.fractions[fi];
      cell.topics = t;
      cell.views = static_cast<int>(views.size());
      cell.views_per_object = per;
      cell.supervised_per_object.assign(static_cast<std::size_t>(C), 0.0);
      cell.unsupervised_per_object.assign(static_cast<std::size_t>(C), 0.0);
      std::vector<int> truth;
      std::vector<int> sup_pred;
      std::vector<int> uns_pred;
      const bool every = std::all_of(per.begin(), per.end(), [](int n) { return n >= 2; });
      const bool by_theta = o.mot_classifier == ClutterMotClassifier::kTheta;
      if (!vocabulary || !every) {
        cell.note = "an object has fewer than 2 training views: no model";
        if (!by_theta) {
          cell.theta = ClutterCell::Theta{};
          cell.theta->supervised_per_object.assign(static_cast<std::size_t>(C), 0.0);
        }
        // every held-out render counts as wrong (unclassified)
        for (int c = 0; c < C; ++c) {
          for (std::size_t v = 0; v < d.held[static_cast<std::size_t>(c)].size(); ++v) {
            truth.push_back(c);
            sup_pred.push_back(-1);
            uns_pred.push_back(-1);
          }
        }
      } else {
        topics::Corpus corpus(vocabulary->size());
        for (const auto& v : views) corpus.add_tokens(words_of(v));
        const topics::LdaModel lda = views_lda(corpus, t, d.seed);
        const Eigen::MatrixXd theta = recognition::document_theta(lda, corpus).theta;
        topics::Corpus held(vocabulary->size());
        for (int c = 0; c < C; ++c) {
          for (const auto& h : d.held[static_cast<std::size_t>(c)]) {
            held.add_tokens(words_of(h));
            truth.push_back(c);
          }
        }
        const Eigen::MatrixXd held_theta =
            truth.empty() ? Eigen::MatrixXd() : recognition::document_theta(lda, held).theta;
        const topics::MotFit sup = topics::fit_mot(theta, labels, objects, o.mot);
        // The supervised MoT's classifier (o.mot_classifier): docs' theta or their words;
        // log_phi / background: the objects' word multinomials (pooled only; background with
        // mot_word_background), fitted to the same labels as model.
        struct WordModels {
          Eigen::MatrixXd log_phi;
          topics::BackgroundWordModel background;
        };
        const auto classify = [&](const topics::MotModel& model, const WordModels& word_models,
                                  const Eigen::MatrixXd& docs_theta,
                                  const topics::Corpus& docs) -> std::vector<int> {
          const Eigen::MatrixXd& log_phi = word_models.log_phi;
          const topics::BackgroundWordModel& background = word_models.background;
          switch (o.mot_classifier) {
            case ClutterMotClassifier::kWords:
              return topics::classify_mot_words(model, lda, docs).predicted;
            case ClutterMotClassifier::kPooled:
              if (o.mot_word_background) {
                return topics::pool_word_scores(model, topics::classify_mot_words(model, lda, docs),
                                                topics::background_word_scores(background, docs),
                                                o.mot_word_weight)
                    .predicted;
              }
              return topics::pool_word_multinomials(model,
                                                    topics::classify_mot_words(model, lda, docs),
                                                    log_phi, docs, o.mot_word_weight)
                  .predicted;
            case ClutterMotClassifier::kTheta:
              break;
          }
          return topics::classify_mot(model, docs_theta).predicted;
        };
        const auto word_multinomials = [&](const std::vector<int>& with_labels) {
          WordModels m;
          if (o.mot_classifier != ClutterMotClassifier::kPooled) return m;
          if (o.mot_word_background) {
            m.background = topics::fit_background_word_model(corpus, with_labels, C);
          } else if (o.mot_word_per_view) {
            m.log_phi = weighted_word_multinomials(corpus, with_labels, C,
                                                   per_view_weights(corpus, with_labels));
          } else {
            m.log_phi = topics::fit_word_multinomials(corpus, with_labels, C);
          }
          return m;
        };
        const WordModels word_models = word_multinomials(labels);
        if (!by_theta) {
          cell.theta = ClutterCell::Theta{};
          cell.theta->supervised_per_object.assign(static_cast<std::size_t>(C), 0.0);
        }
        if (!truth.empty()) {
          sup_pred = classify(sup.model, word_models, held_theta, held);
          if (!by_theta) {
            const auto [acc, per_object] =
                label_accuracy(truth, topics::classify_mot(sup.model, held_theta).predicted, C);
            cell.theta->supervised = acc;
            cell.theta->supervised_per_object = per_object;
          }
        }
        // Held-out pushes: the other seeds' push views through this seed's vocabulary, LDA
        // and supervised MoT.
        if (all.size() > 1) {
          topics::Corpus other(vocabulary->size());
          std::vector<int> other_labels;
          for (const auto& e : all) {
            if (e.seed == d.seed) continue;
            for (std::size_t v = 0; v < e.views[fi].size(); ++v) {
              other.add_tokens(words_of(e.views[fi][v]));
              other_labels.push_back(e.labels[fi][v]);
            }
          }
          if (!other_labels.empty()) {
            const Eigen::MatrixXd other_theta = recognition::document_theta(lda, other).theta;
            const auto [acc, per_object] = label_accuracy(
                other_labels, classify(sup.model, word_models, other_theta, other), C);
            cell.cross_seed = acc;
            cell.cross_seed_per_object = per_object;
            if (!by_theta) {
              const auto [t_acc, t_per_object] = label_accuracy(
                  other_labels, topics::classify_mot(sup.model, other_theta).predicted, C);
              cell.theta->cross_seed = t_acc;
              cell.theta->cross_seed_per_object = t_per_object;
            }
          }
        }
        // Diagnostic: each trial's views classified by a supervised MoT fitted to the other
        // trials' views (the same LDA): push-like held-out views instead of renders.
        {
          const auto& trial_of = d.trials[fi];
          int right = 0;
          int theta_right = 0;
          int n = 0;
          for (int held_trial = 0; held_trial < o.trials && o.trials > 1; ++held_trial) {
            std::vector<int> train_labels(labels.size(), -1);
            std::vector<std::size_t> test;
            std::vector<int> train_per(static_cast<std::size_t>(C), 0);
            for (std::size_t v = 0; v < labels.size(); ++v) {
              if (trial_of[v] == held_trial) {
                test.push_back(v);
              } else {
                train_labels[v] = labels[v];
                ++train_per[static_cast<std::size_t>(labels[v])];
              }
            }
            if (test.empty() ||
                !std::all_of(train_per.begin(), train_per.end(), [](int k) { return k >= 2; })) {
              continue;
            }
            const topics::MotFit fold = topics::fit_mot(theta, train_labels, objects, o.mot);
            Eigen::MatrixXd test_theta(static_cast<Eigen::Index>(test.size()), theta.cols());
            for (std::size_t i = 0; i < test.size(); ++i) {
              test_theta.row(static_cast<Eigen::Index>(i)) =
                  theta.row(static_cast<Eigen::Index>(test[i]));
            }
            const auto pred = classify(fold.model, word_multinomials(train_labels), test_theta,
                                       corpus.subset(test));
            const auto theta_pred = by_theta
                                        ? std::vector<int>()
                                        : topics::classify_mot(fold.model, test_theta).predicted;
            for (std::size_t i = 0; i < test.size(); ++i) {
              right += pred[i] == labels[test[i]] ? 1 : 0;
              if (!by_theta) theta_right += theta_pred[i] == labels[test[i]] ? 1 : 0;
              ++n;
            }
          }
          if (n > 0) cell.cross_trial = share(right, n);
          if (n > 0 && !by_theta) cell.theta->cross_trial = share(theta_right, n);
        }
        try {
          topics::MotOptions uo = o.mot;
          uo.classes = C;
          const topics::MotFit uns = topics::fit_mot_unsupervised(theta, uo);
          std::vector<std::vector<int>> counts(static_cast<std::size_t>(C),
                                               std::vector<int>(static_cast<std::size_t>(C), 0));
          for (std::size_t v = 0; v < uns.assignment.size(); ++v) {
            const int k = uns.assignment[v];
            if (k >= 0 && k < C)
              ++counts[static_cast<std::size_t>(k)][static_cast<std::size_t>(labels[v])];
          }
          const std::vector<int> name = best_assignment(counts);
          if (!truth.empty()) {
            for (int k : topics::classify_mot(uns.model, held_theta).predicted) {
              uns_pred.push_back(k >= 0 && k < C ? name[static_cast<std::size_t>(k)] : -1);
            }
          }
        } catch (const Error& e) {
          cell.note = std::string("unsupervised: ") + e.what();
          uns_pred.assign(truth.size(), -1);
        }
      }
      cell.supervised_confusion = recognition::confusion_matrix(truth, sup_pred, objects, objects);
      cell.unsupervised_confusion =
          recognition::confusion_matrix(truth, uns_pred, objects, objects);
      for (int c = 0; c < C; ++c) {
        const auto uc = static_cast<std::size_t>(c);
        const int n = cell.supervised_confusion.row_total(c);
        cell.supervised_per_object[uc] = share(cell.supervised_confusion.counts[uc][uc], n);
        cell.unsupervised_per_object[uc] = share(cell.unsupervised_confusion.counts[uc][uc], n);
      }
      cell.supervised = cell.supervised_confusion.accuracy();
      cell.unsupervised = cell.unsupervised_confusion.accuracy();
      cells.push_back(std::move(cell));
      bar.tick();
    }
  }
}

// The cells of one T: mean, min and max over seeds x fractions, and the band: per fraction the
// mean over seeds, its min and max over the fractions.
struct TopicSummary {
  int topics = 0;
  double mean = 0, worst = 1, best = 0;  // over seeds x fractions
  double band_low = 1, band_high = 0;    // over fractions of the seed mean
  double u_mean = 0, u_worst = 1, u_best = 0;
  double u_band_low = 1, u_band_high = 0;
  double seed_sd = 0;  // sd over seeds of the mean over fractions (supervised)
  // Held-out pushes (supervised): mean over the cells that have them; nullopt: none.
  std::optional<double> cross_trial, cross_seed;
  // With a classifier other than theta: theta's (eq 7.3) means over the same cells.
  std::optional<double> theta_mean, theta_cross_trial, theta_cross_seed;
};

std::vector<TopicSummary> summarise(const std::vector<ClutterCell>& cells,
                                    const ClutterExperimentOptions& o) {
  std::vector<TopicSummary> out;
  for (int t : o.topics) {
    TopicSummary s;
    s.topics = t;
    int n = 0;
    std::map<double, std::pair<double, int>> sup_f;
    std::map<double, std::pair<double, int>> uns_f;
    std::map<std::uint64_t, std::pair<double, int>> sup_s;
    std::pair<double, int> ct{0, 0};
    std::pair<double, int> cs{0, 0};
    std::pair<double, int> th{0, 0};
    std::pair<double, int> th_ct{0, 0};
    std::pair<double, int> th_cs{0, 0};
    for (const auto& c : cells) {
      if (c.topics != t) continue;
      ++n;
      s.mean += c.supervised;
      s.u_mean += c.unsupervised;
      s.worst = std::min(s.worst, c.supervised);
      s.best = std::max(s.best, c.supervised);
      s.u_worst = std::min(s.u_worst, c.unsupervised);
      s.u_best = std::max(s.u_best, c.unsupervised);
      sup_f[c.fraction].first += c.supervised;
      ++sup_f[c.fraction].second;
      uns_f[c.fraction].first += c.unsupervised;
      ++uns_f[c.fraction].second;
      sup_s[c.seed].first += c.supervised;
      ++sup_s[c.seed].second;
      if (c.cross_trial) {
        ct.first += *c.cross_trial;
        ++ct.second;
      }
      if (c.cross_seed) {
        cs.first += *c.cross_seed;
        ++cs.second;
      }
      if (c.theta) {
        th.first += c.theta->supervised;
        ++th.second;
        if (c.theta->cross_trial) {
          th_ct.first += *c.theta->cross_trial;
          ++th_ct.second;
        }
        if (c.theta->cross_seed) {
          th_cs.first += *c.theta->cross_seed;
          ++th_cs.second;
        }
      }
    }
    if (th.second > 0) s.theta_mean = th.first / th.second;
    if (th_ct.second > 0) s.theta_cross_trial = th_ct.first / th_ct.second;
    if (th_cs.second > 0) s.theta_cross_seed = th_cs.first / th_cs.second;
    if (ct.second > 0) s.cross_trial = ct.first / ct.second;
    if (cs.second > 0) s.cross_seed = cs.first / cs.second;
    if (n == 0) continue;
    s.mean /= n;
    s.u_mean /= n;
    for (const auto& [f, v] : sup_f) {
      s.band_low = std::min(s.band_low, v.first / v.second);
      s.band_high = std::max(s.band_high, v.first / v.second);
    }
    for (const auto& [f, v] : uns_f) {
      s.u_band_low = std::min(s.u_band_low, v.first / v.second);
      s.u_band_high = std::max(s.u_band_high, v.first / v.second);
    }
    if (sup_s.size() > 1) {
      double m = 0;
      for (const auto& [seed, v] : sup_s) m += v.first / v.second;
      m /= static_cast<double>(sup_s.size());
      double ss = 0;
      for (const auto& [seed, v] : sup_s) ss += std::pow(v.first / v.second - m, 2);
      s.seed_sd = std::sqrt(ss / static_cast<double>(sup_s.size() - 1));
    }
    out.push_back(s);
  }
  return out;
}

// The confusion matrix of one (fraction, T) summed over the seeds.
recognition::ConfusionMatrix summed(const std::vector<ClutterCell>& cells, double fraction, int t,
                                    bool supervised) {
  recognition::ConfusionMatrix m;
  for (const auto& c : cells) {
    if (c.topics != t || c.fraction != fraction) continue;
    const auto& x = supervised ? c.supervised_confusion : c.unsupervised_confusion;
    if (m.rows.empty()) {
      m = x;
      continue;
    }
    for (std::size_t r = 0; r < m.counts.size(); ++r) {
      for (std::size_t k = 0; k < m.counts[r].size(); ++k) m.counts[r][k] += x.counts[r][k];
      m.unclassified[r] += x.unclassified[r];
    }
  }
  return m;
}

// Best and worst (fraction, T) by the supervised accuracy of the seeds' summed matrix.
std::pair<std::pair<double, int>, std::pair<double, int>> best_worst(
    const std::vector<ClutterCell>& cells, const ClutterExperimentOptions& o) {
  std::pair<double, int> best{o.fractions.front(), o.topics.front()};
  std::pair<double, int> worst = best;
  double hi = -1, lo = 2;
  for (double f : o.fractions) {
    for (int t : o.topics) {
      const double a = summed(cells, f, t, true).accuracy();
      if (a > hi) {
        hi = a;
        best = {f, t};
      }
      if (a < lo) {
        lo = a;
        worst = {f, t};
      }
    }
  }
  return {best, worst};
}

// Fig 8-3: accuracy against T (log-spaced positions as listed), the fractions' spread as a band,
// supervised (blue) and unsupervised (orange); the line the mean over seeds x fractions.
void draw_figure(const std::vector<TopicSummary>& s, const fs::path& file) {
  const int w = 720, h = 440, left = 70, right = 20, top = 40, bottom = 60;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto x_of = [&](std::size_t i) {
    return left + static_cast<int>((w - left - right) *
                                   (s.size() > 1 ? static_cast<double>(i) / (s.size() - 1) : 0.5));
  };
  const auto y_of = [&](double a) { return top + static_cast<int>((h - top - bottom) * (1 - a)); };
  for (int g = 0; g <= 10; ++g) {
    const int y = y_of(g / 10.0);
    cv::line(img, {left, y}, {w - right, y}, cv::Scalar(225, 225, 225), 1);
    cv::putText(img, std::to_string(g * 10), {left - 35, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  const cv::Scalar blue(180, 119, 31), orange(14, 127, 255);
  const cv::Scalar blue_band(235, 215, 200), orange_band(190, 225, 255);
  for (int pass = 0; pass < 2; ++pass) {
    const bool sup = pass == 0;
    std::vector<cv::Point> poly;
    for (std::size_t i = 0; i < s.size(); ++i)
      poly.emplace_back(x_of(i), y_of(sup ? s[i].band_high : s[i].u_band_high));
    for (std::size_t i = s.size(); i-- > 0;)
      poly.emplace_back(x_of(i), y_of(sup ? s[i].band_low : s[i].u_band_low));
    if (!poly.empty()) {
      cv::Mat overlay = img.clone();
      cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{poly},
                   sup ? blue_band : orange_band);
      cv::addWeighted(overlay, 0.6, img, 0.4, 0, img);
    }
  }
  for (int pass = 0; pass < 2; ++pass) {
    const bool sup = pass == 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const cv::Point p(x_of(i), y_of(sup ? s[i].mean : s[i].u_mean));
      cv::circle(img, p, 4, sup ? blue : orange, -1, cv::LINE_AA);
      if (i > 0) {
        cv::line(img, {x_of(i - 1), y_of(sup ? s[i - 1].mean : s[i - 1].u_mean)}, p,
                 sup ? blue : orange, 2, cv::LINE_AA);
      }
    }
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    cv::putText(img, std::to_string(s[i].topics), {x_of(i) - 8, h - bottom + 20},
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  cv::line(img, {left, y_of(0.9)}, {w - right, y_of(0.9)}, cv::Scalar(120, 120, 120), 1);
  cv::putText(img, "topics T", {w / 2 - 30, h - 15}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "held-out accuracy, %", {5, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "supervised MoT", {w - 300, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, blue, 1,
              cv::LINE_AA);
  cv::putText(img, "unsupervised MoT", {w - 160, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, orange, 1,
              cv::LINE_AA);
  if (!cv::imwrite(file.string(), img)) throw Error(file.string() + ": cannot write the figure");
}

core::Json theta_json(const ClutterCell::Theta& t) {
  return core::Json{{"supervised", t.supervised},
                    {"supervised_per_object", t.supervised_per_object},
                    {"cross_trial", t.cross_trial ? core::Json(*t.cross_trial) : core::Json()},
                    {"cross_seed", t.cross_seed ? core::Json(*t.cross_seed) : core::Json()},
                    {"cross_seed_per_object", t.cross_seed_per_object}};
}

core::Json cell_json(const ClutterCell& c) {
  return core::Json{{"seed", c.seed},
                    {"fraction", c.fraction},
                    {"topics", c.topics},
                    {"views", c.views},
                    {"views_per_object", c.views_per_object},
                    {"supervised", c.supervised},
                    {"unsupervised", c.unsupervised},
                    {"supervised_per_object", c.supervised_per_object},
                    {"unsupervised_per_object", c.unsupervised_per_object},
                    {"supervised_confusion", c.supervised_confusion.to_json()},
                    {"unsupervised_confusion", c.unsupervised_confusion.to_json()},
                    {"cross_trial", c.cross_trial ? core::Json(*c.cross_trial) : core::Json()},
                    {"cross_seed", c.cross_seed ? core::Json(*c.cross_seed) : core::Json()},
                    {"cross_seed_per_object", c.cross_seed_per_object},
                    {"theta", c.theta ? theta_json(*c.theta) : core::Json()},
                    {"note", c.note}};
}

}  // namespace

std::vector<int> best_assignment(const std::vector<std::vector<int>>& counts) {
  const std::size_t n = counts.size();
  if (n > 8) throw Error("best_assignment: at most 8 clusters");
  for (const auto& r : counts) {
    if (r.size() != n) throw Error("best_assignment: the counts must be square");
  }
  std::vector<int> p(n);
  std::iota(p.begin(), p.end(), 0);
  std::vector<int> best = p;
  long long hi = -1;
  do {
    long long s = 0;
    for (std::size_t k = 0; k < n; ++k) s += counts[k][static_cast<std::size_t>(p[k])];
    if (s > hi) {
      hi = s;
      best = p;
    }
  } while (std::next_permutation(p.begin(), p.end()));
  return best;
}

ClutterExperimentOptions ClutterExperimentOptions::resolved() const {
  ClutterExperimentOptions o = *this;
  if (!quick) return o;
  if (!o.seeds.empty()) o.seeds = {o.seeds.front()};
  o.trials = 1;
  o.pushes = 3;
  o.width = 240;
  o.height = 180;
  o.fractions = {0.5, 0.7};
  o.topics = {4, 8};
  o.words = 60;
  o.held_out = 6;
  return o;
}

void ClutterExperimentOptions::validate() const {
  const auto need = [](bool ok, const std::string& what) {
    if (!ok) throw Error(what);
  };
  need(!seeds.empty(), "--seeds: at least one seed");
  need(std::set<std::uint64_t>(seeds.begin(), seeds.end()).size() == seeds.size(),
       "--seeds: a seed is repeated");
  need(trials >= 1 && trials <= 100, "--trials: must be in [1, 100]");
  need(pushes >= 1 && pushes <= 100, "--pushes: must be in [1, 100]");
  need(!fractions.empty(), "--fractions: at least one fraction");
  for (double f : fractions) {
    need(std::isfinite(f) && f > 0 && f < 1, "--fractions: each must be in (0, 1)");
  }
  need(std::set<double>(fractions.begin(), fractions.end()).size() == fractions.size(),
       "--fractions: a fraction is repeated");
  need(!topics.empty(), "--topics: at least one number of topics");
  for (int t : topics) need(t >= 2 && t <= 1000, "--topics: each must be in [2, 1000]");
  need(std::set<int>(topics.begin(), topics.end()).size() == topics.size(),
       "--topics: a number of topics is repeated");
  need(words >= 2 && words <= 100000, "--words: must be in [2, 100000]");
  need(view_step >= 1 && view_step <= 1000, "--view-step: must be in [1, 1000]");
  need(min_features >= 1 && min_features <= 100000, "--min-features: must be in [1, 100000]");
  need(dilate >= 0 && dilate <= 100, "--dilate: must be in [0, 100]");
  need(std::isfinite(fps) && fps > 0 && fps <= 100, "--fps: must be in (0, 100]");
  need(width >= 64 && width <= 4096, "--width: must be in [64, 4096]");
  need(height >= 48 && height <= 4096, "--height: must be in [48, 4096]");
  need(held_out >= 1 && held_out <= 1000, "--held-out: must be in [1, 1000]");
  need(std::isfinite(min_shift) && min_shift >= 0.01 && min_shift <= 0.3,
       "--min-shift: must be in [0.01, 0.3]");
  need(std::isfinite(max_shift) && max_shift >= min_shift && max_shift <= 0.3,
       "--max-shift: must be in [--min-shift, 0.3]");
  need(attempts >= 1 && attempts <= 20, "--attempts: must be in [1, 20]");
  need(std::isfinite(sweep_margin) && sweep_margin >= 0 && sweep_margin <= 0.1,
       "--sweep-margin: must be in [0, 0.1]");
  need(std::isfinite(depth_split) && depth_split >= 0 && depth_split <= 0.2,
       "--depth-split: must be in [0, 0.2]");
  need(erode >= 0 && erode <= 50, "--erode: must be in [0, 50]");
  need(std::isfinite(dense.touch_fm) && dense.touch_fm >= 0 && dense.touch_fm <= 1,
       "--seg-touch-fm: must be in [0, 1]");
  need(std::isfinite(mot_word_weight) && mot_word_weight >= 0 && mot_word_weight <= 1,
       "--mot-word-weight: must be in [0, 1]");
  need(!mot_word_background || mot_classifier == ClutterMotClassifier::kPooled,
       "--mot-word-background: only with --mot-classifier pooled");
  need(background == "plain" || background == "photo" || background == "moving",
       "--background: must be plain, photo or moving");
  need(!cache.empty(), "--cache: required");
  const std::vector<std::string> named = names_of(objects);
  need(named.size() >= 2 && named.size() <= 8, "--objects: 2 to 8 objects");
  std::vector<std::string> all = named;
  for (const auto& c : names_of(clutter)) all.push_back(c);
  need(std::set<std::string>(all.begin(), all.end()).size() == all.size(),
       "--objects/--clutter: a name is repeated");
  need(all.size() <= 8, "--objects/--clutter: at most 8 objects on the table");
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  for (const auto& n : all) {
    try {
      (void)catalogue.get(n);
    } catch (const Error&) {
      throw Error("--objects/--clutter: unknown object '" + n + "'");
    }
  }
}

std::string ClutterExperimentResult::brief() const {
  std::string b = message + "\n";
  if (cells.empty()) return b;
  const auto s = summarise(cells, options);
  b += "   T  supervised mean [worst, best] band          unsupervised mean [worst, best] band"
       "      pushes: other trial  other seed\n";
  const auto pct = [](const std::optional<double>& v) {
    return v ? core::printf_string("%5.1f%%", 100 * *v) : std::string("     -");
  };
  for (const auto& t : s) {
    b += core::printf_string(
        "  %2d  %5.1f%% [%5.1f, %5.1f] %5.1f-%5.1f   %5.1f%% [%5.1f, %5.1f] %5.1f-%5.1f   "
        "      %s      %s\n",
        t.topics, 100 * t.mean, 100 * t.worst, 100 * t.best, 100 * t.band_low, 100 * t.band_high,
        100 * t.u_mean, 100 * t.u_worst, 100 * t.u_best, 100 * t.u_band_low, 100 * t.u_band_high,
        pct(t.cross_trial).c_str(), pct(t.cross_seed).c_str());
  }
  if (options.mot_classifier != ClutterMotClassifier::kTheta) {
    b += core::printf_string(
        "supervised MoT by %s%s; the same models by theta (eq 7.3), paired:\n"
        "   T  renders  other trial  other seed\n",
        std::string(core::choice_name(options.mot_classifier, kClutterMotClassifierNames)).c_str(),
        options.mot_classifier == ClutterMotClassifier::kPooled
            ? core::printf_string(" (word weight %.2f%s%s%s)", options.mot_word_weight,
                                  options.mot_word_background ? ", shared background" : "",
                                  options.mot_word_per_view && !options.mot_word_background
                                      ? ", views weighed alike"
                                      : "",
                                  options.right_angle_words ? ", right-angle words" : "")
                  .c_str()
            : "");
    for (const auto& t : s) {
      b += core::printf_string("  %2d   %s       %s      %s\n", t.topics, pct(t.theta_mean).c_str(),
                               pct(t.theta_cross_trial).c_str(), pct(t.theta_cross_seed).c_str());
    }
  }
  const auto [best, worst] = best_worst(cells, options);
  const auto m_best = summed(cells, best.first, best.second, true);
  const auto m_worst = summed(cells, worst.first, worst.second, true);
  b += core::printf_string("best (fraction %.1f, T %d), supervised, summed over seeds: %.1f%%\n",
                           best.first, best.second, 100 * m_best.accuracy());
  b += m_best.format(true);
  b += core::printf_string("worst (fraction %.1f, T %d), supervised, summed over seeds: %.1f%%\n",
                           worst.first, worst.second, 100 * m_worst.accuracy());
  b += m_worst.format(true);
  return b;
}

ClutterExperimentResult run_clutter_experiment(const ClutterExperimentOptions& options,
                                               const core::Provenance& provenance) {
  const ClutterExperimentOptions o = options.resolved();
  o.validate();
  for (const auto& f : {o.json, o.figure}) {
    if (!f.empty() && fs::exists(f) && !o.overwrite) {
      throw Error(f.string() + ": already exists (use --overwrite to replace it)");
    }
  }
  ClutterExperimentResult r;
  r.options = o;
  const std::vector<std::string> objects = names_of(o.objects);
  const auto t0 = Clock::now();
  // 1. Record what is not cached (trials interleaved: trial 1 of every object first).
  fs::create_directories(o.cache);
  for (const std::uint64_t seed : o.seeds) {
    const core::Json key = recording_key(o, seed);
    std::unique_ptr<sim::SimulatedRobot> robot;
    core::ProgressBar bar(static_cast<std::size_t>(o.trials) * objects.size(),
                          "clutter: seed " + std::to_string(seed) + " trials", o.progress);
    for (int trial = 0; trial < o.trials; ++trial) {
      for (std::size_t oi = 0; oi < objects.size(); ++oi) {
        const fs::path dir = trial_dir(o.cache, seed, objects[oi], trial);
        if (!read_cache(dir, key, o.overwrite)) {
          if (!robot) {
            LearnOptions lo;
            lo.objects = o.objects;
            lo.clutter = o.clutter;
            lo.background = o.background;
            lo.seed = seed;
            lo.width = o.width;
            lo.height = o.height;
            robot = std::make_unique<sim::SimulatedRobot>(learn_table(lo),
                                                          sim::ObjectCatalogue::load_default());
          }
          record_trial(*robot, o, seed, oi, objects[oi], trial, dir, provenance);
        }
        bar.tick();
      }
    }
    robot.reset();  // one GL context at a time
    const fs::path held = o.cache / ("seed_" + std::to_string(seed)) / "held_out";
    if (!read_cache(held, key, o.overwrite)) record_held_out(o, seed, objects, held, provenance);
  }
  r.record_seconds = seconds_since(t0);
  // The pushes as the manifests list them.
  for (const std::uint64_t seed : o.seeds) {
    for (int trial = 0; trial < o.trials; ++trial) {
      for (const auto& name : objects) {
        const fs::path dir = trial_dir(o.cache, seed, name, trial);
        const auto m = read_cache(dir, recording_key(o, seed), false);
        if (!m) throw Error(dir.string() + ": missing from the cache");
        const std::vector<ClutterPush> pushes = clutter_manifest_pushes(
            *m, dir / "clutter_cache.json", seed, name, trial, trial_dir({}, seed, name, trial));
        r.pushes.insert(r.pushes.end(), pushes.begin(), pushes.end());
      }
    }
  }
  int executed = 0;
  int moved = 0;
  for (const auto& p : r.pushes) {
    executed += p.episode.empty() ? 0 : 1;
    moved += p.moved_intended ? 1 : 0;
  }
  r.message = core::printf_string(
      "experiment clutter: %zu seeds, %zu pushes (%d executed, %d moved their object)",
      o.seeds.size(), r.pushes.size(), executed, moved);
  if (!o.record_only) {
    // 2. Segment every push once (all fractions), read the held-out renders, sweep.
    const auto t1 = Clock::now();
    sim::TableOptions arm_table;
    arm_table.objects = {objects.front()};
    arm_table.width = 64;
    arm_table.height = 48;
    std::optional<robot::ArmState> arm_state;
    std::vector<SeedData> data;
    const std::string key = views_key(o);
    {
      // The arm's kinematics (the robot's own knowledge) for cutting it out of the views.
      const sim::SimulatedRobot arm_robot(arm_table, sim::ObjectCatalogue::load_default());
      core::ProgressBar bar(static_cast<std::size_t>(executed), "clutter: segmenting", o.progress);
      for (const std::uint64_t seed : o.seeds) {
        SeedData d;
        d.seed = seed;
        d.views.resize(o.fractions.size());
        d.labels.resize(o.fractions.size());
        d.trials.resize(o.fractions.size());
        for (const auto& p : r.pushes) {
          if (p.seed != seed || p.episode.empty()) continue;
          const int label = static_cast<int>(std::find(objects.begin(), objects.end(), p.object) -
                                             objects.begin());
          const fs::path ep = o.cache / p.episode;
          const fs::path vf = views_file(ep, o);
          std::optional<ViewsByFraction> cached = read_clutter_views(vf, key, o.fractions.size());
          if (!cached) {
            cached = push_views(ep, o, arm_robot.arm(), arm_state);
            write_clutter_views(vf, key, *cached);
          }
          ViewsByFraction& v = *cached;
          for (std::size_t fi = 0; fi < v.size(); ++fi) {
            for (auto& x : v[fi]) {
              d.views[fi].push_back(std::move(x));
              d.labels[fi].push_back(label);
              d.trials[fi].push_back(p.trial);
            }
          }
          bar.tick();
        }
        const fs::path held = o.cache / ("seed_" + std::to_string(seed)) / "held_out";
        d.held.resize(objects.size());
        for (std::size_t oi = 0; oi < objects.size(); ++oi) {
          for (int v = 0; v < o.held_out; ++v) {
            char file[32];
            std::snprintf(file, sizeof file, "view_%03d.png", v);
            const cv::Mat image = features::read_image(held / objects[oi] / file);
            std::snprintf(file, sizeof file, "mask_%03d.png", v);
            const cv::Mat mask =
                cv::imread((held / objects[oi] / file).string(), cv::IMREAD_GRAYSCALE);
            if (mask.empty() || mask.size() != image.size()) {
              throw Error((held / objects[oi] / file).string() +
                          ": missing or not the view's size");
            }
            const features::Features f =
                features::extract_features(image, o.features, features::dilated(mask, o.dilate));
            if (f.size() < o.min_features) continue;  // as score_self_supervision
            d.held[oi].push_back(f.descriptors.clone());
          }
        }
        data.push_back(std::move(d));
      }
    }
    core::ProgressBar bar(o.seeds.size() * o.fractions.size() * o.topics.size(), "clutter: sweep",
                          o.progress);
    for (const auto& d : data) sweep_seed(d, data, o, objects, r.cells, bar);
    bar.finish();
    r.sweep_seconds = seconds_since(t1);
  }
  // 3. The record.
  core::Json doc =
      core::result_document(kClutterExperimentFormat, kClutterExperimentVersion, provenance);
  std::vector<std::string> fr;
  doc["options"] = core::Json{
      {"objects", objects},
      {"clutter", names_of(o.clutter)},
      {"background", o.background},
      {"seeds", o.seeds},
      {"trials", o.trials},
      {"pushes", o.pushes},
      {"fractions", o.fractions},
      {"topics", o.topics},
      {"segmentation", std::string(core::choice_name(o.segmentation, kPushSegmentationNames))},
      {"words", o.words},
      {"view_step", o.view_step},
      {"min_features", o.min_features},
      {"dilate", o.dilate},
      {"fps", o.fps},
      {"width", o.width},
      {"height", o.height},
      {"held_out", o.held_out},
      {"min_shift", o.min_shift},
      {"max_shift", o.max_shift},
      {"attempts", o.attempts},
      {"sweep_margin", o.sweep_margin},
      {"depth_split", o.depth_split},
      {"erode", o.erode},
      {"seg_touch_fm", o.dense.touch_fm},
      {"mot_classifier",
       std::string(core::choice_name(o.mot_classifier, kClutterMotClassifierNames))},
      {"mot_word_weight", o.mot_word_weight},
      {"mot_word_background", o.mot_word_background},
      {"mot_word_per_view", o.mot_word_per_view},
      {"right_angle_words", o.right_angle_words},
      {"quick", o.quick},
      {"record_only", o.record_only}};
  core::Json pushes = core::Json::array();
  for (const auto& p : r.pushes) {
    pushes.push_back({{"seed", p.seed},
                      {"object", p.object},
                      {"trial", p.trial + 1},
                      {"index", p.index},
                      {"outcome", p.outcome},
                      {"moved_intended", p.moved_intended},
                      {"only_intended", p.only_intended},
                      {"replaced", p.replaced},
                      {"attempts", p.attempts},
                      {"failed", p.failed},
                      {"executed", !p.episode.empty()}});
  }
  doc["pushes"] = pushes;
  core::Json cells = core::Json::array();
  for (const auto& c : r.cells) cells.push_back(cell_json(c));
  doc["cells"] = cells;
  if (!r.cells.empty()) {
    core::Json summary = core::Json::array();
    for (const auto& s : summarise(r.cells, o)) {
      summary.push_back(
          {{"topics", s.topics},
           {"supervised",
            {{"mean", s.mean},
             {"worst", s.worst},
             {"best", s.best},
             {"band", {s.band_low, s.band_high}},
             {"seed_sd", s.seed_sd}}},
           {"unsupervised",
            {{"mean", s.u_mean},
             {"worst", s.u_worst},
             {"best", s.u_best},
             {"band", {s.u_band_low, s.u_band_high}}}},
           {"cross_trial", s.cross_trial ? core::Json(*s.cross_trial) : core::Json()},
           {"cross_seed", s.cross_seed ? core::Json(*s.cross_seed) : core::Json()},
           {"theta",
            s.theta_mean
                ? core::Json{{"supervised", *s.theta_mean},
                             {"cross_trial", s.theta_cross_trial ? core::Json(*s.theta_cross_trial)
                                                                 : core::Json()},
                             {"cross_seed",
                              s.theta_cross_seed ? core::Json(*s.theta_cross_seed) : core::Json()}}
                : core::Json()}});
    }
    doc["summary"] = summary;
    const auto [best, worst] = best_worst(r.cells, o);
    doc["best"] = {{"fraction", best.first},
                   {"topics", best.second},
                   {"supervised", summed(r.cells, best.first, best.second, true).to_json()},
                   {"unsupervised", summed(r.cells, best.first, best.second, false).to_json()}};
    doc["worst"] = {{"fraction", worst.first},
                    {"topics", worst.second},
                    {"supervised", summed(r.cells, worst.first, worst.second, true).to_json()},
                    {"unsupervised", summed(r.cells, worst.first, worst.second, false).to_json()}};
    if (!o.figure.empty()) {
      draw_figure(summarise(r.cells, o), o.figure);
      doc["figure"] = o.figure.filename().string();
    }
  }
  doc["record_seconds"] = r.record_seconds;
  doc["sweep_seconds"] = r.sweep_seconds;
  r.document = doc;
  if (!o.json.empty()) core::write_json_atomic(o.json, doc);
  return r;
}

}  // namespace proprio::loop
