// The Summary convention (issue 14): every Result a command's library call returns, and every
// Summary of a run that a caller reads, has a one-line `message` and `brief()`. Checked at compile
// time over the list below: a type added without them does not build. A new command's Result goes
// on the list.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/import.hpp"
#include "proprio/episode/summary.hpp"
#include "proprio/eval/dataset_evaluation.hpp"
#include "proprio/eval/segment_episode.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/features/vocabulary_build.hpp"
#include "proprio/geometry/calib_runs.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/stereo_check.hpp"
#include "proprio/geometry/triangulation.hpp"
#include "proprio/loop/learn.hpp"
#include "proprio/loop/learn_report.hpp"
#include "proprio/loop/object_words.hpp"
#include "proprio/loop/push_run.hpp"
#include "proprio/loop/self_supervision_run.hpp"
#include "proprio/planning/interception_experiment.hpp"
#include "proprio/recognition/experiment_runs.hpp"
#include "proprio/recognition/image_quantize.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/recognition/recognize_runs.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "proprio/segmentation/fm_baseline.hpp"
#include "proprio/segmentation/graph_cut.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/sim/calibration.hpp"
#include "proprio/sim/dataset.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/sim_runs.hpp"
#include "proprio/sim/views.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/dirichlet_fit.hpp"
#include "proprio/topics/dirichlet_mixture.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_runs.hpp"
#include "proprio/topics/mixture_of_topics.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio {
namespace {

template <class... S>
constexpr bool kAllSummaries = (core::Summary<S> && ...);

// The Results of the commands' library calls (docs/architecture.md's table).
static_assert(kAllSummaries<
              episode::EpisodeInfoResult, episode::CheckResult, episode::ImportResult,
              eval::SegmentEpisodeResult, eval::DatasetEvaluationResult, features::VocabularyInfo,
              features::VocabularyBuildResult, loop::LearnResult, loop::LearnReportResult,
              loop::PushRunResult, loop::PushEvaluationResult, loop::SelfSupervisionResult,
              planning::InterceptionRunResult, planning::InterceptionSweepResult,
              recognition::QuantizeImagesResult, recognition::MotTrainResult,
              recognition::MotClassifyResult, recognition::MotUpdateResult, sim::SimDatasetResult,
              topics::LdaTrainingResult, topics::LdaPerplexityResult>);

// The Results whose brief() is a report or listing made by the call (issue 14: they held only
// `report` or `lines`; the CLI now prints their brief()).
static_assert(kAllSummaries<geometry::CalibRun, sim::SimRun, recognition::ExperimentRun,
                            recognition::MotInfo, recognition::RecognizeTrainResult,
                            recognition::RecognizeClassifyResult, topics::LdaTopWords>);

// The Summaries of the algorithms those calls run.
static_assert(
    kAllSummaries<geometry::DltSummary, geometry::StereoCheckSummary,
                  geometry::BatchTriangulationSummary, loop::TopDownResult, robot::IkSummary,
                  robot::TrackSummary, segmentation::FmSummary, segmentation::GraphCutSummary,
                  segmentation::MlSummary, sim::SimCalibrationSummary, sim::RecordSummary,
                  sim::ViewsSummary, topics::BatchLdaSummary, topics::DirichletFitSummary,
                  topics::DirichletMixtureSummary, topics::SharedPrecisionSummary,
                  topics::InferenceSummary, topics::MotFitSummary, topics::OnlineLdaSummary>);

struct OnlyBrief {
  [[nodiscard]] std::string brief() const { return "b"; }
};
struct OnlyMessage {
  std::string message;
};
static_assert(!core::Summary<OnlyBrief> && !core::Summary<OnlyMessage>,
              "the check must refuse a type with only one of the two");

TEST(SummaryConvention, TheMessageIsTheBriefsFirstLine) {
  EXPECT_EQ(core::first_line("learned 3 of 7 objects\n  mug 50%"), "learned 3 of 7 objects");
  EXPECT_EQ(core::first_line("one line"), "one line");
  EXPECT_EQ(core::first_line(""), "");
}

// A Summary made by a run carries its message (not only the type: the producer sets it).
TEST(SummaryConvention, ARunSetsItsMessage) {
  topics::Corpus corpus(3);
  for (const std::vector<std::int32_t>& tokens :
       {std::vector<std::int32_t>{0, 0, 1}, {1, 1, 1, 2}, {0, 2, 2}})
    corpus.add_tokens(tokens);
  topics::OnlineLdaOptions o;
  o.num_topics = 2;
  o.batch_size = 2;
  o.passes = 1;
  const topics::OnlineLdaResult r = topics::train_online_lda(corpus, o);
  EXPECT_FALSE(r.summary.message.empty());
  EXPECT_EQ(r.summary.message, core::first_line(r.summary.brief()));
}

}  // namespace
}  // namespace proprio
