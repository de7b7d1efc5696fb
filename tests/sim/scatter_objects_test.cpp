// The scatter scenario with chosen objects (thesis 6.3.3): exactly those objects, wandering in
// and out of the camera's view, deterministic in the seed; bad object lists.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>

#include "proprio/core/error.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/sim/recorder.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {

namespace fs = std::filesystem;

const ObjectCatalogue& catalogue() {
  static const ObjectCatalogue c = ObjectCatalogue::load_default();
  return c;
}

RecordOptions scatter_options() {
  RecordOptions o;
  o.scenario = "scatter";
  o.object = "calculator";
  o.scatter_objects = {"calculator", "bike", "bottle", "giraffe"};
  o.width = 160;
  o.height = 120;
  o.push_speed = 0.2;
  o.still_before = 0.08;
  o.still_after = 0.08;
  return o;
}

std::string message_of(const RecordOptions& o) {
  try {
    (void)plan_scenario(o, catalogue());
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ScatterObjects, PlanHoldsExactlyTheChosenObjects) {
  const ScenarioPlan plan = plan_scenario(scatter_options(), catalogue());
  std::multiset<std::string> types;
  for (const auto& o : plan.scene.objects) types.insert(o.type);
  EXPECT_EQ(types, (std::multiset<std::string>{"calculator", "bike", "bottle", "giraffe"}));
  EXPECT_EQ(plan.target, "calculator");
  ASSERT_EQ(plan.walkers.size(), 3U);
  EXPECT_TRUE(plan.sliders.empty());
  for (const auto& w : plan.walkers) {
    EXPECT_NE(w.name, plan.target);
    EXPECT_GE(w.position.y(), w.y_min);  // behind the push corridor
    EXPECT_GE(w.position.x(), plan.walk_min.x());
    EXPECT_LE(w.position.x(), plan.walk_max.x());
    for (const auto& v : plan.walkers) {
      if (&v != &w) {
        EXPECT_GT((w.position - v.position).norm(), w.radius + v.radius);
      }
    }
  }
}

TEST(ScatterObjects, EveryTargetAndSeedFindsRoomForFourObjects) {
  RecordOptions o = scatter_options();
  for (const std::string target : {"calculator", "bike", "bottle", "giraffe"}) {
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      o.object = target;
      o.seed = seed;
      const ScenarioPlan plan = plan_scenario(o, catalogue());
      EXPECT_EQ(plan.walkers.size(), 3U) << target << " " << seed;
    }
  }
}

TEST(ScatterObjects, PlanIsDeterministicInTheSeed) {
  RecordOptions o = scatter_options();
  const ScenarioPlan a = plan_scenario(o, catalogue());
  const ScenarioPlan b = plan_scenario(o, catalogue());
  o.seed = 8;
  const ScenarioPlan c = plan_scenario(o, catalogue());
  ASSERT_EQ(a.walkers.size(), b.walkers.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.walkers.size(); ++i) {
    EXPECT_EQ(a.walkers[i].position, b.walkers[i].position);
    EXPECT_EQ(a.walkers[i].heading, b.walkers[i].heading);
    differs = differs || a.walkers[i].position != c.walkers[i].position;
  }
  EXPECT_TRUE(differs);
}

TEST(ScatterObjects, InViewWalkersStayInTheNarrowerBox) {
  RecordOptions o = scatter_options();
  const ScenarioPlan wide = plan_scenario(o, catalogue());
  o.scatter_in_view = true;
  const ScenarioPlan narrow = plan_scenario(o, catalogue());
  EXPECT_LT(wide.walk_min.x(), narrow.walk_min.x());
  EXPECT_GT(wide.walk_max.x(), narrow.walk_max.x());
  for (const auto& w : narrow.walkers) {
    EXPECT_GE(w.position.x(), narrow.walk_min.x());
    EXPECT_LE(w.position.x(), narrow.walk_max.x());
  }
}

TEST(ScatterObjects, BadListsAreErrorsNamingTheProblem) {
  RecordOptions o = scatter_options();
  o.scatter_objects = {"calculator", "unicorn"};
  EXPECT_NE(message_of(o).find("'unicorn'"), std::string::npos) << message_of(o);
  o.scatter_objects = {"calculator", "bike", "bike"};
  EXPECT_NE(message_of(o).find("'bike' is given twice"), std::string::npos) << message_of(o);
  o.scatter_objects = {"bike", "bottle"};  // the target calculator is missing
  EXPECT_NE(message_of(o).find("'calculator' is not one of the scatter objects"), std::string::npos)
      << message_of(o);
  o = scatter_options();
  o.scenario = "push";
  EXPECT_NE(message_of(o).find("scatter scenario only"), std::string::npos) << message_of(o);
}

TEST(ScatterObjects, EachObjectIsSeenAndTheWalkersMove) {
  const fs::path out = test::temp_dir() / "scatter_objects";
  fs::remove_all(out);
  RecordOptions o = scatter_options();
  const RecordSummary s =
      record_episode(out, o, core::Provenance::current({"scatter_objects_test"}, 3), catalogue());
  for (const auto& p : episode::check_episode(out)) ADD_FAILURE() << p.message;
  EXPECT_GT(s.target_moved, 0.02);
  const episode::Episode e = episode::read_episode(out);
  std::map<std::string, int> id_of;
  for (const auto& obj : e.objects()) id_of[obj.name] = obj.id;
  for (const char* n : {"calculator", "scatter-bike", "scatter-bottle", "scatter-giraffe"})
    ASSERT_TRUE(id_of.count(n)) << n;
  std::map<std::string, int> frames_seen;
  std::map<std::string, cv::Point2d> first_centre, last_centre;
  for (int i = 0; i < e.frame_count(); ++i) {
    const cv::Mat m = e.mask(i);
    for (const auto& [name, id] : id_of) {
      const cv::Mat in = m == id;
      if (cv::countNonZero(in) == 0) continue;
      ++frames_seen[name];
      const cv::Moments mo = cv::moments(in, true);
      const cv::Point2d c(mo.m10 / mo.m00, mo.m01 / mo.m00);
      if (!first_centre.count(name)) first_centre[name] = c;
      last_centre[name] = c;
    }
  }
  for (const char* n : {"calculator", "scatter-bike", "scatter-bottle", "scatter-giraffe"}) {
    EXPECT_GT(frames_seen[n], 0) << n << " never in view";
  }
  // The walkers move over the short episode (0.06-0.2 m/s for about a second).
  for (const char* n : {"scatter-bike", "scatter-bottle", "scatter-giraffe"}) {
    if (frames_seen[n] < 2) continue;
    EXPECT_GT(cv::norm(first_centre[n] - last_centre[n]), 1.0) << n;
  }
  fs::remove_all(out);
}

}  // namespace
}  // namespace proprio::sim
