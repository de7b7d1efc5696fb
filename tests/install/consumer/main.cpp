// Uses the installed headers, libraries and data: one call into every module, including a
// headless render of the simulated scene, and checks each answer.
#include <cstdio>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/core/data_dir.hpp"
#include "proprio/core/version.hpp"
#include "proprio/episode/arm_sample.hpp"
#include "proprio/eval/mask_metrics.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/planning/stereo_rig.hpp"
#include "proprio/recognition/confusion.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/segmentation/optical_flow.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/scene_description.hpp"
#include "proprio/sim/world.hpp"
#include "proprio/topics/synthetic.hpp"

namespace {

int failures = 0;

void check(bool ok, const char* what) {
  std::printf("%-12s %s\n", what, ok ? "ok" : "FAILED");
  if (!ok) ++failures;
}

}  // namespace

int main() {
  using namespace proprio;
  const auto data = core::data_directory();
  check(std::string(kVersion).size() > 0 && !data.empty(), "core");

  geometry::Camera cam;
  cam.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  cam.t << 0, 0, 2;
  const Eigen::Vector2d x = cam.project(Eigen::Vector3d(0.2, -0.1, 0.0));
  check((x - Eigen::Vector2d(370, 215)).norm() < 1e-9, "geometry");

  check(episode::arm_csv_header(5).size() > 5, "episode");

  cv::Mat descriptors(40, 2, CV_32F);
  for (int i = 0; i < 40; ++i) {
    descriptors.at<float>(i, 0) = static_cast<float>(i < 20 ? 0 : 10) + 0.01f * i;
    descriptors.at<float>(i, 1) = 0.0f;
  }
  features::KmeansOptions k;
  k.words = 2;
  k.threads = 1;
  check(features::build_vocabulary(descriptors, k).vocabulary.size() == 2, "features");

  topics::SyntheticCorpusOptions c;
  c.num_topics = 2;
  c.num_words = 20;
  c.num_documents = 10;
  check(topics::make_synthetic_corpus(c).topics.rows() == 2, "topics");

  robot::ArmState arm(robot::Arm::load(data / "models" / "arm_standalone.xml"));
  check(arm.ee_position(robot::JointVector::Zero()).norm() > 0.1, "robot");

  // The simulated scene, rendered headless (OSMesa), from the installed catalogue and models.
  sim::SceneDescription d = sim::default_scene();
  d.cameras.at(0).width = 160;
  d.cameras.at(0).height = 120;
  const sim::World world = sim::World::build(d, sim::ObjectCatalogue::load_default());
  sim::Renderer renderer(world);
  const cv::Mat rgb = renderer.rgb(world, world.camera_names().at(0));
  check(rgb.cols == 160 && rgb.rows == 120 && cv::countNonZero(rgb.reshape(1)) > 0, "sim");

  const std::vector<int> truth{0, 1, 1};
  const std::vector<int> predicted{0, 1, 0};
  check(recognition::confusion_matrix(truth, predicted, {"a", "b"}, {"a", "b"}).correct() == 2,
        "recognition");

  cv::Mat1b a(48, 64, static_cast<unsigned char>(0));
  cv::randu(a, 0, 255);
  segmentation::DenseFlow flow(segmentation::FlowMethod::kDisFast);
  check(flow.compute(a, a).size() == a.size(), "segmentation");

  check(planning::visible(planning::default_stereo_rig(), Eigen::Vector3d(0.4, 0.0, 0.1)),
        "planning");

  cv::Mat mask(10, 10, CV_8U, cv::Scalar(0));
  mask(cv::Rect(0, 0, 5, 10)).setTo(255);
  check(eval::compare_masks(mask, mask).jaccard == 1.0, "eval");

  std::printf("proprio %s: %s\n", kVersion, failures == 0 ? "every module ok" : "failures");
  return failures == 0 ? 0 : 1;
}
