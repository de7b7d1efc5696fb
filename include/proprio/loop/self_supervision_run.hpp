#pragma once
// `proprio selfsupervise`: the self-supervision loop (loop/self_supervision.hpp) as one library
// call: read and check the LDA model and vocabulary, run the learner on a robot, write the
// Mixture of Topics model, the decision log and the pushes' episodes; on the simulated table
// also score it against the ground truth and on held-out views (loop/self_supervision_scoring).

#include <filesystem>
#include <optional>
#include <string>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/loop/self_supervision.hpp"
#include "proprio/loop/self_supervision_scoring.hpp"

namespace proprio::loop {

inline constexpr const char* kSelfSupervisionFormat = "proprio.selfsupervise";

// NOLINTNEXTLINE(bugprone-exception-escape)
struct SelfSupervisionResult {
  SelfSupervisionOptions options;  ///< the run's options (out: the directory the record names)
  Learning learning;
  std::optional<SelfSupervisionScore> score;  ///< on the simulated table
  std::filesystem::path model_file;           ///< out/model.mot, or empty when no class was learned
  std::filesystem::path decisions;            ///< out/decisions.jsonl
  core::Json document;                        ///< format "proprio.selfsupervise"
  std::string message;                        ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    const Learning& l = self.learning;
    v(self.options, {"options", "The run's options"});
    v(l.class_names, {"classes", "The classes learned, one a round"});
    v(l.views_per_class, {"views_per_class", "Training views of each class"});
    v(l.model.names(), {"model_classes", "The classes in the Mixture of Topics (>= 2 views)"});
    v(l.pushes_clear, {"pushes_clear", "Executed pushes in (b)"});
    v(l.pushes_learn, {"pushes_learn", "Executed pushes in (c)"});
    v(l.faults, {"faults", "Logged faults"});
    v(l.stop_reasons, {"stop_reasons", "Per round: why it ended early (empty: it did not)"});
    v(l.round_class, {"round_class", "Per round: the class its views became (-1: none)"});
    v(l.seconds, {"seconds", "Wall clock, s"});
    v(self.model_file, {"model", "The Mixture of Topics model written, or empty"});
    v(self.decisions, {"decisions", "The decision log, one JSON object a line"});
    v(self.score, {"ground_truth", "Scored against the ground truth (simulated table)"});
  }
};

/// The learner on `robot` with the objects re-scattered by `attendant` (C = the number of
/// options.objects): reads the model and vocabulary (Error when their numbers of words differ),
/// writes options.out/episodes/, decisions.jsonl and model.mot (recording the LDA model's and the
/// vocabulary's checksums). Throws Error for bad options or an existing out (unless overwrite).
SelfSupervisionResult run_self_supervision(const SelfSupervisionOptions& options,
                                           robot::Robot& robot, TableAttendant& attendant,
                                           const core::Provenance& provenance);

/// run_self_supervision on a simulated table of options.objects (plain backdrop, seed
/// options.seed), scored against the ground truth and on held-out views; also writes
/// options.out/selfsupervise.json. Throws Error for an unknown or repeated object, more objects
/// than fit on the table (8), or as run_self_supervision.
SelfSupervisionResult run_self_supervision_sim(const SelfSupervisionOptions& options,
                                               const core::Provenance& provenance);

}  // namespace proprio::loop
