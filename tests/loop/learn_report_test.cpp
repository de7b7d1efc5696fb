// The learn report (loop/learn_report.hpp) on a small fixture run directory: every section is on
// the page, every image it references exists and decodes, strings from the files are escaped,
// nothing non-finite is printed, and bad run directories give an Error naming the file.
#include "proprio/loop/learn_report.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <string>

#include "../support/error_of.hpp"
#include "../support/learn_run_fixture.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio::loop {
namespace {

namespace fs = std::filesystem;
using test::error_of;

std::vector<std::string> img_sources(const std::string& page) {
  std::vector<std::string> out;
  const std::regex src("<img src=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(page.begin(), page.end(), src); it != std::sregex_iterator();
       ++it) {
    out.push_back((*it)[1].str());
  }
  return out;
}

LearnReportResult report_of(const fs::path& dir, bool overwrite = false) {
  LearnReportOptions o;
  o.dir = dir;
  o.overwrite = overwrite;
  return write_learn_report(o);
}

void edit_learn_json(const fs::path& dir, const std::function<void(core::Json&)>& edit) {
  core::Json j = core::read_json(dir / "learn.json");
  edit(j);
  core::write_json_atomic(dir / "learn.json", j);
}

TEST(LearnReport, WritesEverySectionAndEveryImageItReferences) {
  test::TempDir tmp("proprio_learn_report_");
  test::write_learn_run_fixture(tmp.path());
  const LearnReportResult r = report_of(tmp.path());
  EXPECT_EQ(r.summary.page, tmp.path() / "report.html");
  EXPECT_EQ(r.summary.pushes, 3);
  EXPECT_EQ(r.summary.pushes_drawn, 2);
  EXPECT_EQ(r.summary.classes, 2);
  EXPECT_EQ(r.summary.decisions, 5);
  EXPECT_TRUE(r.summary.complete);
  EXPECT_DOUBLE_EQ(r.summary.mot_accuracy, 0.85);
  EXPECT_DOUBLE_EQ(r.summary.argmax_accuracy, 0.6);
  EXPECT_EQ(r.document["format"], kLearnReportFormat);
  // table + 2 pushes x (plan, after, overlay, map) + 1 word image.
  EXPECT_EQ(r.summary.image_files, 1 + 2 * 4 + 1);

  const std::string page = core::read_file(r.summary.page);
  for (std::string_view id : kLearnReportSections) {
    EXPECT_NE(page.find(std::string("<section id=\"") + std::string(id) + "\""), std::string::npos)
        << id;
  }
  const auto sources = img_sources(page);
  EXPECT_EQ(static_cast<int>(sources.size()), r.summary.image_files);
  for (const std::string& src : sources) {
    EXPECT_EQ(src.rfind("report/", 0), 0U) << src;  // beside the page, relative
    const cv::Mat m = cv::imread((tmp.path() / src).string(), cv::IMREAD_UNCHANGED);
    EXPECT_FALSE(m.empty()) << src;
  }
  EXPECT_TRUE(fs::exists(tmp.path() / "report" / "summary.json"));
  // Offline: no external resource of any kind.
  EXPECT_EQ(page.find("http://www.w3.org/2000/svg\" width") != std::string::npos, true);
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);
  EXPECT_EQ(page.find("href=\"http"), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  // Strings from the files are escaped, and never NaN or Inf.
  EXPECT_EQ(page.find("<b>bottle</b>"), std::string::npos);
  EXPECT_NE(page.find("&lt;b&gt;bottle&lt;/b&gt; &amp; &quot;cap&quot;"), std::string::npos);
  EXPECT_EQ(page.find("<i>x</i>"), std::string::npos);
  EXPECT_EQ(page.find("nan"), std::string::npos);
  EXPECT_EQ(page.find("inf<"), std::string::npos);
  // Known figures: the accuracies and the per-object accuracy of the MoT matrix (18/20).
  EXPECT_NE(page.find("85.0%"), std::string::npos);
  EXPECT_NE(page.find("90.0%"), std::string::npos);
  EXPECT_NE(page.find("9.8 s in all"), std::string::npos);  // 0.5 + 6 + 2.25 + 1
  // 18 of 20 right: Wilson 95% interval [0.699, 0.972].
  EXPECT_NE(page.find("90.0% [69.9%, 97.2%]"), std::string::npos);
}

TEST(LearnReport, HeldOutAccuracyComesFromTheClassesTruthsNotTheDiagonal) {
  // The columns are the robot's classes, in no row's order, named as the held-out scoring names
  // them ("object_2 (bottle)"): the diagonal (2 + 4 of 40) is not the accuracy; the views given
  // a class learned from their own object are (18 + 16 of 40), whatever "accuracy" says.
  test::TempDir tmp("proprio_learn_report_");
  test::LearnRunFixture f;
  test::write_learn_run_fixture(tmp.path(), f);
  edit_learn_json(tmp.path(), [&](core::Json& j) {
    core::Json& mot = j["held_out"]["mot"];
    mot["columns"] = {"object_2 (" + f.hostile_truth + ")", "object_1 (box)"};
    mot["counts"] = {{2, 18}, {16, 4}};
    mot["accuracy"] = 0.15;
    mot["unclassified"] = {0, 0};
  });
  const LearnReportResult r = report_of(tmp.path());
  EXPECT_DOUBLE_EQ(r.summary.mot_accuracy, 0.85);
  const std::string page = core::read_file(r.summary.page);
  EXPECT_NE(page.find("Mixture of Topics <b>85.0%</b>"), std::string::npos);
  EXPECT_EQ(page.find("15.0%"), std::string::npos);
  EXPECT_NE(page.find("90.0% [69.9%, 97.2%]"), std::string::npos);  // box: 18 of 20
  // Unclassified views count against their object.
  edit_learn_json(tmp.path(), [](core::Json& j) {
    j["held_out"]["mot"]["unclassified"] = {10, 0};
  });
  LearnReportOptions again;
  again.dir = tmp.path();
  again.overwrite = true;
  EXPECT_DOUBLE_EQ(write_learn_report(again).summary.mot_accuracy, 34.0 / 50.0);
}

TEST(LearnReport, ShowsBytesThatAreNotUtf8AsReplacementCharacters) {
  test::TempDir tmp("proprio_learn_report_");
  test::LearnRunFixture f;
  f.models = false;
  test::write_learn_run_fixture(tmp.path(), f);
  // JSON that is not UTF-8 is refused by the parser; a control character in a string is dropped;
  // a file name that is not UTF-8 (a word image) is shown with U+FFFD.
  edit_learn_json(tmp.path(), [](core::Json& j) { j["objects"][0]["truth"] = "bo\x01xy"; });
  cv::imwrite((tmp.path() / "words" / "ob\xFFj.png").string(), cv::Mat(8, 8, CV_8UC3));
  const std::string page = core::read_file(report_of(tmp.path()).summary.page);
  EXPECT_NE(page.find("boxy"), std::string::npos);
  EXPECT_EQ(page.find('\x01'), std::string::npos);
  EXPECT_NE(page.find("ob\xEF\xBF\xBDj"), std::string::npos);
  EXPECT_EQ(page.find('\xFF'), std::string::npos);

  std::string json = core::read_file(tmp.path() / "learn.json");
  json.replace(json.find("bo\\u0001xy"), 10, "b\xFFxy");
  core::write_file_atomic(tmp.path() / "learn.json", json);
  fs::remove(tmp.path() / "report.html");
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find("learn.json:"), std::string::npos);
}

TEST(LearnReport, RefusesToReplaceThePageUnlessTold) {
  test::TempDir tmp("proprio_learn_report_");
  test::write_learn_run_fixture(tmp.path());
  report_of(tmp.path());
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find("--overwrite"), std::string::npos);
  LearnReportOptions o;
  o.dir = tmp.path();
  o.overwrite = true;
  o.out = tmp.path() / "report.html";
  EXPECT_EQ(write_learn_report(o).summary.image_files, 10);
  // Elsewhere, with its images beside it.
  o.out = tmp.path() / "elsewhere" / "page.html";
  fs::create_directories(o.out.parent_path());
  const auto r = write_learn_report(o);
  EXPECT_TRUE(fs::exists(tmp.path() / "elsewhere" / "page" / "table.jpg"));
  EXPECT_NE(core::read_file(o.out).find("src=\"page/table.jpg\""), std::string::npos);
  // A page whose image directory would be the run's pushes/ is refused.
  o.out = tmp.path() / "pushes.html";
  EXPECT_FALSE(error_of([&] { write_learn_report(o); }).empty());
}

TEST(LearnReport, SaysNotRecordedForMissingOptionalItems) {
  test::TempDir tmp("proprio_learn_report_");
  test::LearnRunFixture f;
  f.models = false;
  f.table = false;
  test::write_learn_run_fixture(tmp.path(), f);
  fs::remove_all(tmp.path() / "words");
  edit_learn_json(tmp.path(), [](core::Json& j) {
    j["complete"] = false;
    j.erase("held_out");
    j.erase("timing");
    j.erase("options");
  });
  const LearnReportResult r = report_of(tmp.path());
  EXPECT_FALSE(r.summary.complete);
  EXPECT_EQ(r.summary.mot_accuracy, -1);
  const std::string page = core::read_file(r.summary.page);
  EXPECT_NE(page.find("incomplete"), std::string::npos);
  std::size_t n = 0;
  for (auto p = page.find("Not recorded."); p != std::string::npos;
       p = page.find("Not recorded.", p + 1))
    ++n;
  EXPECT_EQ(n, 4U);  // options, table, held-out, timing
  EXPECT_NE(page.find("12 words (the vocabulary file is not in the run directory)"),
            std::string::npos);
  EXPECT_NE(page.find("3 topics (the model file is not in the run directory)"), std::string::npos);
  EXPECT_NE(page.find("The object model file is not recorded."), std::string::npos);
  for (std::string_view id : kLearnReportSections) {
    EXPECT_NE(page.find(std::string("id=\"") + std::string(id) + "\""), std::string::npos) << id;
  }
}

TEST(LearnReport, ShowsAnUnreadableOptionalModelWithItsProblem) {
  test::TempDir tmp("proprio_learn_report_");
  test::write_learn_run_fixture(tmp.path());
  core::write_file_atomic(tmp.path() / "lda.model", "not a model");
  const std::string page = core::read_file(report_of(tmp.path()).summary.page);
  EXPECT_NE(page.find("Could not be read: "), std::string::npos);
}

TEST(LearnReport, BadRunDirectoriesGiveAnErrorNamingTheFile) {
  test::TempDir tmp("proprio_learn_report_");
  test::write_learn_run_fixture(tmp.path());
  const std::string learn = (tmp.path() / "learn.json").string();
  const auto fails_with = [&](const std::function<void(core::Json&)>& edit,
                              const std::string& part) {
    test::write_learn_run_fixture(tmp.path());
    edit_learn_json(tmp.path(), edit);
    const std::string e = error_of([&] { report_of(tmp.path()); });
    EXPECT_NE(e.find(learn), std::string::npos) << e;
    EXPECT_NE(e.find(part), std::string::npos) << e;
  };
  fails_with([](core::Json& j) { j["format"] = "proprio.selfsupervise"; }, "format");
  fails_with([](core::Json& j) { j["format_version"] = 2; }, "format_version");
  fails_with([](core::Json& j) { j.erase("pushes"); }, "\"pushes\" is missing");
  fails_with([](core::Json& j) { j.erase("held_out"); }, "held_out");  // complete: required
  fails_with([](core::Json& j) { j["pushes"][0]["dir"] = "../../etc"; }, "pushes/0/dir");
  fails_with([](core::Json& j) { j["pushes"][1]["plan"]["start_px"] = {1}; }, "start_px");
  fails_with([](core::Json& j) { j["held_out"]["mot"]["counts"][0] = {1}; }, "counts/0");
  fails_with([](core::Json& j) { j["timing"][0]["seconds"] = -1; }, "seconds");
  fails_with([](core::Json& j) { j["pushes"][1].erase("executed"); },
             "\"pushes/1/executed\" is missing");

  test::write_learn_run_fixture(tmp.path());
  core::write_file_atomic(tmp.path() / "learn.json", "{\"format\": ");
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find(learn), std::string::npos);
  fs::remove(tmp.path() / "learn.json");
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find(learn), std::string::npos);

  // A missing image of an executed push names it.
  test::write_learn_run_fixture(tmp.path());
  fs::remove(tmp.path() / "pushes" / "push_001" / "map.png");
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find("push_001/map.png"), std::string::npos);

  // decisions.jsonl: missing, or a line that is no JSON object (named by its line).
  test::write_learn_run_fixture(tmp.path());
  core::write_file_atomic(tmp.path() / "decisions.jsonl", "{\"event\":\"a\"}\n[1]\n");
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find("decisions.jsonl:2"), std::string::npos);
  fs::remove(tmp.path() / "decisions.jsonl");
  EXPECT_NE(error_of([&] { report_of(tmp.path()); }).find("decisions.jsonl"), std::string::npos);
}

TEST(LearnReport, SaysHowThePerceptionOfAPushComparesWithThePushItself) {
  // Issue 21's speed goal, from each executed push's perception_cpu_seconds and robot_seconds.
  test::TempDir tmp("proprio_learn_report_");
  test::write_learn_run_fixture(tmp.path());
  const std::string line = "Perception of a push";
  EXPECT_EQ(core::read_file(report_of(tmp.path(), true).summary.page).find(line),
            std::string::npos);  // not recorded: no line
  edit_learn_json(tmp.path(), [](core::Json& j) {
    j["pushes"][0]["robot_seconds"] = 4.0;
    j["pushes"][0]["perception_cpu_seconds"] = 1.0;
    j["pushes"][1]["robot_seconds"] = 4.0;
    j["pushes"][1]["perception_cpu_seconds"] = 5.0;
    j["pushes"][2]["robot_seconds"] = 0.0;  // not executed: left out
    j["pushes"][2]["perception_cpu_seconds"] = 9.0;
  });
  const std::string page = core::read_file(report_of(tmp.path(), true).summary.page);
  EXPECT_NE(page.find(line), std::string::npos);
  EXPECT_NE(page.find("3.00 s against 4.00 s a push on average; 1 of 2 pushes perceived in less "
                      "time than they lasted (largest ratio 1.25)"),
            std::string::npos);
  for (const double bad : {-1.0, 2e6}) {
    edit_learn_json(tmp.path(),
                    [bad](core::Json& j) { j["pushes"][1]["perception_cpu_seconds"] = bad; });
    EXPECT_NE(
        error_of([&] { report_of(tmp.path(), true); }).find("pushes/1/perception_cpu_seconds"),
        std::string::npos);
  }
  // A push of no duration gives no ratio (never an infinite one).
  edit_learn_json(tmp.path(), [](core::Json& j) {
    j["pushes"][1]["perception_cpu_seconds"] = 5.0;
    j["pushes"][1]["robot_seconds"] = 0.0;
  });
  const std::string one = core::read_file(report_of(tmp.path(), true).summary.page);
  EXPECT_NE(one.find("1.00 s against 4.00 s a push on average; 1 of 1 pushes"), std::string::npos);
  EXPECT_EQ(one.find("ratio inf"), std::string::npos);
}

TEST(LearnReport, SkipsOverlongDecisionLines) {
  test::TempDir tmp("proprio_learn_report_");
  test::write_learn_run_fixture(tmp.path());
  std::string log = "{\"event\":\"start\"}\n{\"event\":\"";
  log += std::string(kMaxDecisionLineBytes + 10, 'x');
  log += "\"}\n{\"event\":\"end\"}\n";
  core::write_file_atomic(tmp.path() / "decisions.jsonl", log);
  const LearnReportResult r = report_of(tmp.path());
  EXPECT_EQ(r.summary.decisions, 2);
  EXPECT_NE(core::read_file(r.summary.page).find("1 lines longer than"), std::string::npos);
}

}  // namespace
}  // namespace proprio::loop
