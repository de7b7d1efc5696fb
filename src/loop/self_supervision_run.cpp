// `proprio selfsupervise`: the self-supervision loop as one library call.
#include "proprio/loop/self_supervision_run.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/text.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/mot_model_io.hpp"

namespace proprio::loop {

namespace fs = std::filesystem;

namespace {

constexpr int kFormatVersion = 1;
// The most objects a simulated table holds (sim::TableOptions).
constexpr std::size_t kMaxObjects = 8;

struct Inputs {
  topics::LdaModel model;
  features::Vocabulary vocabulary;
  /// The options the run goes by: the caller's, with colour_words turned on when
  /// colour_words_from_model finds the model made with them.
  SelfSupervisionOptions options;
};

Inputs read_inputs(const SelfSupervisionOptions& o) {
  if (o.lda_model.empty()) throw Error("selfsupervise: --model (an LDA model file) is required");
  if (o.vocabulary.empty()) throw Error("selfsupervise: --vocabulary is required");
  if (o.out.empty()) throw Error("selfsupervise: --out is required");
  Inputs in{topics::load_lda_model(o.lda_model), features::read_vocabulary(o.vocabulary), o};
  // A model of the vocabulary's words and the colour words after them was made with colour
  // words: read as it was made (validate again: they do not go with every option).
  if (!o.colour_words && o.colour_words_from_model &&
      in.model.num_words() == features::document_vocabulary_size(in.vocabulary, o.colour)) {
    in.options.colour_words = true;
    try {
      in.options.validate();
    } catch (const Error& e) {
      throw Error(core::cat({o.lda_model.string(), ": made with colour words (",
                             std::to_string(in.model.num_words()), " = the vocabulary's ",
                             std::to_string(in.vocabulary.size()), " + ",
                             std::to_string(o.colour.count()), "), but ", e.what()}));
    }
  }
  // With colour words the model has the vocabulary's words and the colour words after them.
  const int words = features::document_vocabulary_size(in.vocabulary, in.options.document_colour());
  if (words != in.model.num_words()) {
    if (o.colour_words) {
      throw Error(
          core::cat({o.lda_model.string(), ": ", std::to_string(in.model.num_words()),
                     " words, but --colour-words needs the vocabulary's ",
                     std::to_string(in.vocabulary.size()), " + ", std::to_string(o.colour.count()),
                     " colour words = ", std::to_string(words),
                     " (make the model with recognize train --colour-words)"}));
    }
    throw Error(core::cat({o.vocabulary.string(), ": ", std::to_string(in.vocabulary.size()),
                           " words, but the LDA model ", o.lda_model.string(), " has ",
                           std::to_string(in.model.num_words()),
                           ": not the vocabulary the model was made with"}));
  }
  return in;
}

// What marks a directory proprio selfsupervise wrote: a finished run, or its decision log.
constexpr std::string_view kSelfSupervisionMarkers[] = {"selfsupervise.json", "decisions.jsonl"};

// The run is written under a hidden name beside --out and swapped in whole at the end (issue
// 16): a failed or killed run leaves the old directory as it was, and nothing of it stays.
struct StagedOut {
  static const SelfSupervisionOptions& checked(const SelfSupervisionOptions& o) {
    if (fs::exists(o.out) && !o.overwrite) {
      throw Error(o.out.string() + ": already exists (use --overwrite to replace it)");
    }
    return o;
  }
  core::StagedDirectory dir;
  SelfSupervisionOptions options;  ///< as the record names them: out is the final directory
  explicit StagedOut(const SelfSupervisionOptions& o)
      : dir(checked(o).out, o.overwrite, kSelfSupervisionMarkers), options(o) {
    options.out = dir.final_path();
  }
  /// Where the run writes until commit().
  [[nodiscard]] const fs::path& work() const { return dir.staging_path(); }
};

// Writes into `work` (swapped in as options.out at the end); the record names options.out.
SelfSupervisionResult learn(const SelfSupervisionOptions& options, const fs::path& work,
                            robot::Robot& robot, TableAttendant& attendant, const Inputs& in,
                            int classes) {
  SelfSupervisionResult r;
  r.options = options;
  r.learning = learn_by_pushing(robot, attendant, classes, in.model, in.vocabulary, options,
                                work / "episodes", work / "decisions.jsonl", options.progress);
  if (r.learning.model.num_classes() > 0) {
    const std::uint32_t vc = recognition::vocabulary_checksum(in.vocabulary);
    topics::save_mot_model(r.learning.model, topics::mot_basis(in.model, &vc), work / "model.mot");
    r.model_file = options.out / "model.mot";
  }
  r.decisions = options.out / "decisions.jsonl";
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace

std::string SelfSupervisionResult::brief() const {
  const Learning& l = learning;
  std::string s = core::printf_string(
      "learned %d of %d classes from %d views; %d pushes to clear, %d to learn, %d faults, %.0f s",
      l.model.num_classes(), l.classes, static_cast<int>(l.views.labels.size()), l.pushes_clear,
      l.pushes_learn, l.faults, l.seconds);
  if (!score) return s;
  const SelfSupervisionScore& g = *score;
  s += core::printf_string(
      "\nsingulation %.0f%%, %.2f pushes per object cleared, %.0f%% pushes moved only the "
      "intended object, %d off the table, purity %.1f%%",
      100 * g.singulation, g.pushes_per_cleared, 100 * g.only_intended, g.off_table,
      100 * g.purity);
  for (std::size_t c = 0; c < g.class_object.size(); ++c) {
    s += core::printf_string("\n  %s -> %s: %d views, purity %.1f%%", l.class_names[c].c_str(),
                             g.class_object[c].empty() ? "?" : g.class_object[c].c_str(),
                             l.views_per_class[c], 100 * g.class_purity[c]);
  }
  for (const ObjectScore& o : g.objects) {
    s += core::printf_string(
        "\n  %-12s held out %3d: Mixture of Topics %5.1f%%, argmax theta %5.1f%%", o.name.c_str(),
        o.held_out, 100 * o.mot_accuracy, 100 * o.argmax_accuracy);
    if (o.colour_accuracy) s += core::printf_string(", colour %5.1f%%", 100 * *o.colour_accuracy);
    s += core::printf_string("; yaw seen %3.0f deg", o.yaw_range_deg);
  }
  s += core::printf_string("\nheld-out accuracy: Mixture of Topics %.1f%%, argmax theta %.1f%%",
                           100 * g.mot_accuracy, 100 * g.argmax_accuracy);
  if (g.colour_accuracy) s += core::printf_string(", colour %.1f%%", 100 * *g.colour_accuracy);
  for (const LadderRung& rung : g.ladder ? g.ladder->rungs : std::vector<LadderRung>{}) {
    if (rung.classes == 0) continue;  // nothing trained (ceiling only: all but a0, a0_table)
    s += core::printf_string("\n  ladder %-8s %5.1f%% (%d views):", rung.name.c_str(),
                             100 * rung.accuracy, rung.training_views);
    for (std::size_t o = 0; o < rung.per_object.size() && o < g.objects.size(); ++o) {
      s += core::printf_string(" %s %.0f%%", g.objects[o].name.c_str(), 100 * rung.per_object[o]);
    }
  }
  return s;
}

SelfSupervisionResult run_self_supervision(const SelfSupervisionOptions& options,
                                           robot::Robot& robot, TableAttendant& attendant,
                                           const core::Provenance& provenance) {
  options.validate();
  const std::vector<std::string> objects = parse_object_list(options.objects);
  const Inputs in = read_inputs(options);
  StagedOut out(in.options);
  SelfSupervisionResult r =
      learn(out.options, out.work(), robot, attendant, in, static_cast<int>(objects.size()));
  r.document = core::result_document(kSelfSupervisionFormat, kFormatVersion, provenance);
  core::fields_into_json(r, r.document);
  out.dir.commit();
  return r;
}

SelfSupervisionResult run_self_supervision_sim(const SelfSupervisionOptions& options,
                                               const core::Provenance& provenance) {
  options.validate();
  const std::vector<std::string> objects = parse_object_list(options.objects);
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  for (const auto& name : objects) (void)catalogue.get(name);  // Error: unknown object
  if (objects.size() > kMaxObjects) {
    throw Error(core::cat({"objects: ", std::to_string(objects.size()),
                           " objects do not fit on the table (at most ",
                           std::to_string(kMaxObjects), ")"}));
  }
  const Inputs in = read_inputs(options);
  StagedOut out(in.options);
  sim::TableOptions table;
  table.objects = objects;
  table.seed = options.seed;
  table.width = options.width;
  table.height = options.height;
  table.record_masks = options.oracle_ladder;  // the ladder's ground truth (scoring only)
  table.depth = options.depth || options.alone_by_depth ||
                options.topple_ratio > 0;  // an RGB-D camera: Look::depth for the planner
  // One GL context at a time: the table's robot goes before the held-out views are rendered
  // (the attendant keeps its records, not the robot).
  auto robot = std::make_unique<sim::SimulatedRobot>(table, catalogue);
  GroundTruthAttendant attendant(*robot, options.seed);
  SelfSupervisionResult r;
  SelfSupervisionOptions scoring = in.options;
  if (options.ceiling_only) {
    // No pushes: an empty learning (no classes), scored with the ladder's render rungs only.
    r.options = out.options;
    r.message = "ceiling only: no robot run";
    scoring.oracle_ladder = true;
  } else {
    r = learn(out.options, out.work(), *robot, attendant, in, static_cast<int>(objects.size()));
  }
  robot.reset();
  r.score =
      score_self_supervision(r.learning, attendant, objects, in.model, in.vocabulary, scoring);
  r.document = core::result_document(kSelfSupervisionFormat, kFormatVersion, provenance);
  core::fields_into_json(r, r.document);
  core::write_json_atomic(out.work() / "selfsupervise.json", r.document);
  out.dir.commit();
  return r;
}

}  // namespace proprio::loop
