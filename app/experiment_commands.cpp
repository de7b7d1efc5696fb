// proprio experiment ...: the object-modelling experiments of thesis 6.3 (specific vs wide
// dictionary, batch vs online LDA, videos of objects moved about; 7.3.1 with --mot).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/loop/clutter_experiment.hpp"
#include "proprio/recognition/experiment_runs.hpp"
#include "proprio/recognition/recognize_runs.hpp"

namespace proprio::app {
namespace {
using namespace recognition;

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

struct SetArgs {
  SetExperimentRunOptions options;
  int lda_iterations = 100;
  int online_passes = 10;
  int online_batch = 50;
  JsonFlag json;
  bool quiet = false;
};

struct ScatterArgs {
  ScatterExperimentRunOptions options;
  std::string k = "objects,8";
  std::string view_select = "mask";
  JsonFlag json;
  bool quiet = false;
};

void run_set(SetArgs& a, const Invocation& inv, bool dictionary) {
  a.options.dictionary = dictionary;
  a.options.progress = !a.quiet;
  SetExperimentOptions& o = a.options.options;
  o.batch.max_iterations = a.lda_iterations;
  o.online.passes = a.online_passes;
  o.online.batch_size = a.online_batch;
  a.json.refuse({a.options.images});
  const ExperimentRun r = run_set_experiment_files(a.options, inv.provenance(o.seed));
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
}

void run_scatter(ScatterArgs& a, const Invocation& inv) {
  a.options.options.topics = parse_topics(a.k);
  a.options.options.frames.dilate = a.options.options.view_dilate;  // --dilate: both alike
  a.options.options.frames.erode = a.options.options.view_erode;    // --erode: both alike
  a.options.options.frames.erode_min_features = a.options.options.view_erode_min_features;
  a.options.options.view_selection = a.view_select == "bare" ? recognition::ViewSelection::kBareMask
                                                             : recognition::ViewSelection::kMask;
  if (a.options.options.view_erode > 0 && a.options.options.view_dilate > 0) {
    throw Error("--erode needs --dilate 0 (the masks are either grown or shrunk)");
  }
  a.options.progress = !a.quiet;
  std::vector<std::filesystem::path> paths = a.options.episodes;
  paths.insert(paths.end(), a.options.view_episodes.begin(), a.options.view_episodes.end());
  paths.emplace_back(a.options.views);
  paths.emplace_back(a.options.vocabulary);
  // Several seeds: one JSON each, "{seed}" in --json standing for the seed.
  const std::string placeholder = "{seed}";
  const bool several = a.options.seeds.size() > 1;
  if (several && a.json.given() && a.json.path().find(placeholder) == std::string::npos) {
    throw Error("with several --seeds, --json needs {seed} in its name (one file per seed)");
  }
  auto json_of = [&](std::uint64_t seed) {
    std::string path = a.json.path();
    const auto at = path.find(placeholder);
    if (at != std::string::npos) path.replace(at, placeholder.size(), std::to_string(seed));
    return JsonFlag(path);
  };
  const std::vector<std::uint64_t> seeds = a.options.seeds.empty()
                                               ? std::vector<std::uint64_t>{a.options.options.seed}
                                               : a.options.seeds;
  for (const std::uint64_t seed : seeds) json_of(seed).refuse(paths);
  // Each seed printed and written as soon as it is done: a long run stopped part-way keeps them.
  const ScatterRunDoneFn write = [&](std::size_t i, const ExperimentRun& run) {
    if (several) std::printf("== seed %llu\n", static_cast<unsigned long long>(seeds[i]));
    std::fputs(run.brief().c_str(), stdout);
    std::fflush(stdout);
    json_of(seeds[i]).write(run.document);
  };
  (void)run_scatter_experiments_files(a.options, inv.provenance(a.options.options.seed), write);
}

struct ClutterArgs {
  loop::ClutterExperimentOptions options;
  std::string segmentation = "dense";
  std::string mot_classifier = "pooled";
  bool quiet = false;
};

void run_clutter(ClutterArgs& a, const Invocation& inv) {
  a.options.segmentation =
      a.segmentation == "sparse" ? loop::PushSegmentation::kSparse : loop::PushSegmentation::kDense;
  for (const auto& [name, value] : loop::kClutterMotClassifierNames) {
    if (name == a.mot_classifier) a.options.mot_classifier = value;
  }
  a.options.progress = !a.quiet;
  const loop::ClutterExperimentResult r = loop::run_clutter_experiment(
      a.options, inv.provenance(a.options.seeds.empty() ? 1 : a.options.seeds.front()));
  std::fputs(r.brief().c_str(), stdout);
}

void add_clutter_options(CLI::App* cmd, ClutterArgs& a) {
  loop::ClutterExperimentOptions& o = a.options;
  cmd->add_option("--cache", o.cache,
                  "Directory of the recorded pushes and held-out renders (made, or reused when "
                  "recorded with the same options)")
      ->required();
  cmd->add_option("--json", o.json, "Write the results as JSON to this file (atomically)");
  cmd->add_option("--figure", o.figure, "Write Fig 8-3 (accuracy against topics) as PNG");
  cmd->add_option("--objects", o.objects, "Objects pushed and scored, catalogue names")
      ->capture_default_str();
  cmd->add_option("--clutter", o.clutter, "More catalogue objects on the table; '' none")
      ->capture_default_str();
  cmd->add_option("--background", o.background, "Backdrop: plain, photo or moving")
      ->capture_default_str();
  cmd->add_option("--seeds", o.seeds, "Seeds, one table each (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--trials", o.trials, "Trials per object (each re-places the scene)")
      ->capture_default_str();
  cmd->add_option("--pushes", o.pushes, "Pushes per trial")->capture_default_str();
  cmd->add_option("--fractions", o.fractions,
                  "Segmentation thresholds: mask = map >= fraction x its maximum (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--topics", o.topics, "Numbers of LDA topics T (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--segmentation", a.segmentation, "Push segmentation: dense or sparse")
      ->capture_default_str()
      ->check(CLI::IsMember({"dense", "sparse"}));
  cmd->add_option("--words", o.words, "Vocabulary words")->capture_default_str();
  cmd->add_option("--view-step", o.view_step, "Views: every n-th frame from the touch")
      ->capture_default_str();
  cmd->add_option("--min-features", o.min_features, "Features a view needs")->capture_default_str();
  cmd->add_option("--dilate", o.dilate, "Grow the masks by this many px")->capture_default_str();
  cmd->add_option("--fps", o.fps, "Frame rate of the push episodes")->capture_default_str();
  cmd->add_option("--width", o.width, "Image width, px")->capture_default_str();
  cmd->add_option("--height", o.height, "Image height, px")->capture_default_str();
  cmd->add_option("--held-out", o.held_out, "Held-out renders per object")->capture_default_str();
  cmd->add_option("--min-shift", o.min_shift, "Push target: at least this far from the object, m")
      ->capture_default_str();
  cmd->add_option("--max-shift", o.max_shift, "Push target: at most this far, m")
      ->capture_default_str();
  cmd->add_option("--attempts", o.attempts,
                  "Planning attempts per planned push (a new target each; the scene re-placed "
                  "after an object not seen or off the table and every second failure); 1: the "
                  "session-21 harness")
      ->capture_default_str();
  cmd->add_option("--sweep-margin", o.sweep_margin,
                  "Push planner: least gap between the pushed object's swept region and its "
                  "neighbours, m; 0: off")
      ->capture_default_str();
  cmd->add_option("--depth-split", o.depth_split,
                  "Push planner: split a blob at a depth step of this height, m; 0: off")
      ->capture_default_str();
  cmd->add_option("--seg-touch-fm", o.dense.touch_fm,
                  "dense: regions in the baseline's touch cut score at least this x the map's "
                  "peak (MlOptions::touch_fm); 0 off")
      ->capture_default_str();
  cmd->add_option("--erode", o.erode,
                  "Erode the view masks by this many px (after the arm is cut out, before "
                  "--dilate); 0: none")
      ->capture_default_str();
  cmd->add_option("--mot-classifier", a.mot_classifier,
                  "The supervised MoT classifies a view by its theta (eq 7.3), its words (the "
                  "MoT's bound on log p(w|c)) or its words pooled with each object's word "
                  "multinomial; other than theta, theta's scores are printed beside")
      ->capture_default_str()
      ->check(CLI::IsMember({"theta", "words", "pooled"}));
  cmd->add_option("--mot-word-weight", o.mot_word_weight,
                  "pooled: the word multinomials' weight in [0, 1]")
      ->capture_default_str();
  cmd->add_flag("--mot-word-background", o.mot_word_background,
                "pooled: each object's word multinomial with a background shared by all objects, "
                "each view scored at its own share of background");
  cmd->add_flag("--mot-word-per-view,!--no-mot-word-per-view", o.mot_word_per_view,
                "pooled: every view of an object weighs the same in its word multinomial (its "
                "counts scaled to the mean view's number of words; the default since session "
                "30); --no-mot-word-per-view: the pooled counts");
  cmd->add_flag("--right-angle-words", o.right_angle_words,
                "Every document (push views, renders) counts the words of its descriptors "
                "turned by 0, 90, 180 and 270 degrees: words that do not change when an object "
                "lies on its side or turns (session 31)");
  cmd->add_flag("--quick", o.quick,
                "Small and fast: first seed, 1 trial of 3 pushes, 240x180, fractions 0.5,0.7, "
                "topics 4,8");
  cmd->add_flag("--record-only", o.record_only, "Record the pushes into the cache and stop");
  cmd->add_flag("--overwrite", o.overwrite,
                "Replace a cache recorded with other options, and --json / --figure");
  cmd->add_flag("-q,--quiet", a.quiet, "No progress bar");
}

void add_set_options(CLI::App* cmd, SetArgs& a) {
  cmd->add_option("--images", a.options.images, "Folder-per-class image set (Caltech-256's layout)")
      ->required();
  cmd->add_option("--set-a", a.options.options.set_a,
                  "Classes of set A (the specific dictionary's); default: the first half")
      ->delimiter(',');
  cmd->add_option("--set-b", a.options.options.set_b, "Classes of set B; default: the other half")
      ->delimiter(',');
  cmd->add_option("--wide", a.options.options.wide, "Classes of the wide dictionary; default: all")
      ->delimiter(',');
  cmd->add_option("--words", a.options.options.kmeans.words, "Words per dictionary")
      ->capture_default_str();
  cmd->add_option("--dictionary-images", a.options.options.dictionary_images,
                  "Training images per class for a dictionary")
      ->capture_default_str();
  cmd->add_option("--per-image", a.options.options.descriptors_per_image,
                  "Descriptors drawn per dictionary image")
      ->capture_default_str();
  cmd->add_option("--test-per-class", a.options.options.test_per_class, "Test images per class")
      ->capture_default_str();
  cmd->add_option("--lda-iterations", a.lda_iterations, "Batch LDA: EM iterations at most")
      ->capture_default_str();
  cmd->add_option("--passes", a.online_passes, "Online LDA: passes over the training images")
      ->capture_default_str();
  cmd->add_option("--batch", a.online_batch, "Online LDA: images per mini-batch")
      ->capture_default_str();
  cmd->add_option("--seed", a.options.options.seed, "Seed of the split, dictionaries and LDA")
      ->capture_default_str();
  bind_options(cmd, a.options.options.features);
  cmd->add_flag("-q,--quiet", a.quiet, "No progress bar");
  a.json.add_to(cmd, "the confusion matrices");
}

}  // namespace

void register_experiment_commands(CLI::App& root, const Invocation& inv) {
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
  sc->add_option("--episodes", s->options.episodes, "Episode directories, or directories of them")
      ->required();
  sc->add_option("--views", s->options.views,
                 "Folder-per-object views; folder names = object names");
  sc->add_option("--view-episodes", s->options.view_episodes,
                 "Held-out episodes whose frames, cut by the ground-truth masks, give the views "
                 "(alternate blocks of --view-block frames name the topics and test); instead "
                 "of --views");
  sc->add_option("--view-block", s->options.options.view_block,
                 "With --view-episodes: frames per block of the naming / test split")
      ->capture_default_str();
  sc->add_option("--objects", s->options.objects,
                 "With --view-episodes: the objects (catalogue names)")
      ->delimiter(',');
  sc->add_option("--view-step", s->options.options.view_step,
                 "With --view-episodes: every n-th frame")
      ->capture_default_str();
  sc->add_option("--view-min-features", s->options.options.view_min_features,
                 "With --view-episodes: least features of a view")
      ->capture_default_str();
  sc->add_option("--view-select", s->view_select,
                 "With --view-episodes: a view is kept by the features of the mask it is cut by "
                 "(mask) or of the object's bare mask (bare: the same views whatever --dilate / "
                 "--erode)")
      ->capture_default_str()
      ->check(CLI::IsMember({"mask", "bare"}));
  sc->add_option("--dilate", s->options.options.view_dilate,
                 "Grow the object masks by this many px (the views' and each-object frames')")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  sc->add_option("--erode", s->options.options.view_erode,
                 "Shrink the object masks by this many px instead (views and each-object frames; "
                 "only with --dilate 0)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  sc->add_option("--erode-min-features", s->options.options.view_erode_min_features,
                 "Adaptive shrink (with --erode): each mask shrunk only as far as it keeps this "
                 "many of its bare mask's features, by at most --erode px (0: off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10000));
  sc->add_option("--k", s->k,
                 "Numbers of topics K, comma-separated; objects = the number of objects")
      ->capture_default_str();
  sc->add_option("--vocabulary", s->options.vocabulary,
                 "Vocabulary file (default: built from the frames)");
  sc->add_option("--words", s->options.options.kmeans.words,
                 "Words of a dictionary built from the frames")
      ->capture_default_str();
  sc->add_option("--dictionary-frames", s->options.options.dictionary_frames,
                 "Frames sampled for that dictionary")
      ->capture_default_str();
  sc->add_option("--per-frame", s->options.options.descriptors_per_frame,
                 "Descriptors drawn per frame")
      ->capture_default_str();
  bind_choice(sc, s->options.options.frames.region,
              {"region",
               "What of a frame is a document: objects (the views' objects by the ground-truth "
               "masks), each-object (one document per object, masks), whole, target, blobs, masks"},
              kFrameRegionNames);
  sc->add_option("--masks", s->options.options.frames.masks, "Region masks: directory of masks");
  sc->add_option("--frame-step", s->options.options.frame_step, "Use every n-th frame")
      ->capture_default_str();
  sc->add_option("--batch", s->options.options.online.batch_size, "Frames per mini-batch")
      ->capture_default_str();
  sc->add_option("--passes", s->options.options.online.passes, "Passes over the frames")
      ->capture_default_str();
  sc->add_option("--mapping-fraction", s->options.options.mapping_fraction,
                 "Fraction of each object's views (labelled) that names the topics; the rest test")
      ->capture_default_str();
  sc->add_option("--seed", s->options.options.seed, "Seed")->capture_default_str();
  sc->add_option("--seeds", s->options.seeds,
                 "With --view-episodes: several seeds over one feature extraction (comma-"
                 "separated; one run each, --json with {seed} in its name); instead of --seed")
      ->delimiter(',');
  sc->add_flag("--split-by-episode", s->options.options.split_by_episode,
               "With --view-episodes: the first --mapping-fraction of the view episodes give the "
               "labelled views, the others the test views (instead of alternate blocks)");
  sc->add_flag("--mot", s->options.options.mot,
               "Also classify the test views by a supervised Mixture of Topics (thesis 7.1) "
               "fitted to the labelled views' theta");
  sc->add_option("--mot-smoothing", s->options.options.mot_options.smoothing,
                 "With --mot: theta smoothing s, (1 - s) theta + s / T before the log")
      ->capture_default_str();
  sc->add_option("--mot-smoothing-grid", s->options.options.mot_smoothing_grid,
                 "With --mot: also evaluate the supervised MoT at these smoothings (comma-"
                 "separated), with either prior (tuning)")
      ->delimiter(',');
  sc->add_option("--mot-grid-components", s->options.options.mot_grid_components,
                 "With --mot-smoothing-grid: fit the grid's mixture once per cap, the most "
                 "Dirichlet components per object (comma-separated, each in [2, 1000])")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(2, 1000));
  sc->add_option("--mot-grid-word-weights", s->options.options.mot_grid_word_weights,
                 "With --mot-smoothing-grid: also pool each object model's classification by "
                 "words with the objects' word multinomials at these weights (comma-separated, "
                 "each in [0, 1]; 0: the MoT by words alone, 1: naive Bayes on the words)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 1.0));
  bind_options(sc, s->options.options.frames.features);
  sc->add_flag("-q,--quiet", s->quiet, "No progress bar");
  s->json.add_to(sc, "the confusion matrices");
  sc->callback([s, &inv] { run_scatter(*s, inv); });

  auto c = std::make_shared<ClutterArgs>();
  auto* cl = exp->add_subcommand(
      "clutter",
      "Pushes of book, bottle, CD and giraffe in clutter, segmented bottom-up; supervised and "
      "unsupervised Mixture of Topics against topics and segmentation threshold (thesis 8.2, "
      "Fig 8-3, Tables 8.1-8.2)");
  add_clutter_options(cl, *c);
  cl->callback([c, &inv] { run_clutter(*c, inv); });
}

}  // namespace proprio::app
