// proprio report DIR: the page of a learn run from the command line (known answers on a fixture
// run directory: every section, every image it references exists; bad input: one line, exit 2).
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "../support/learn_run_fixture.hpp"
#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

const char* const kSections[] = {"summary", "table",  "pushes",   "segmentation", "words",
                                 "topics",  "models", "held-out", "timing",       "decisions"};

TEST(ReportCli, WritesThePageWithEverySectionAndItsImages) {
  test::TempDir tmp("proprio_report_cli_");
  const fs::path run = tmp.path() / "run";
  test::write_learn_run_fixture(run);
  const auto r = run_cli("report " + run.string() + " --json " + (tmp.path() / "r.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("held-out MoT accuracy 85.0%"), std::string::npos) << r.out;
  const std::string page = core::read_file(run / "report.html");
  for (const char* id : kSections) {
    EXPECT_NE(page.find(std::string("<section id=\"") + id + "\""), std::string::npos) << id;
  }
  const std::regex src("<img src=\"([^\"]*)\"");
  int images = 0;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), src); it != std::sregex_iterator();
       ++it, ++images) {
    EXPECT_TRUE(fs::is_regular_file(run / (*it)[1].str())) << (*it)[1].str();
  }
  EXPECT_EQ(images, 10);
  const core::Json doc = core::read_json(tmp.path() / "r.json");
  EXPECT_EQ(doc["format"], "proprio.learn_report");
  EXPECT_EQ(doc["summary"]["image_files"], 10);
  test::expect_schema_valid("learn_report.schema.json", tmp.path() / "r.json");
  test::expect_schema_valid("learn_report.schema.json", run / "report" / "summary.json");

  // Again: refused without --overwrite, one line, exit 2; done with it.
  const auto again = run_cli("report " + run.string());
  EXPECT_EQ(again.code, 2);
  EXPECT_EQ(test::line_count(again.err), 1) << again.err;
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
  EXPECT_EQ(run_cli("report " + run.string() + " --overwrite").code, 0);
  // Elsewhere with --out.
  const fs::path out = tmp.path() / "page.html";
  ASSERT_EQ(run_cli("report " + run.string() + " --out " + out.string()).code, 0);
  EXPECT_TRUE(fs::is_regular_file(tmp.path() / "page" / "table.jpg"));
}

TEST(ReportCli, MalformedLearnJsonExitsTwoNamingTheFile) {
  test::TempDir tmp("proprio_report_cli_");
  test::write_learn_run_fixture(tmp.path());
  const std::string learn = (tmp.path() / "learn.json").string();
  core::write_file_atomic(learn, "{\"format\": \"proprio.learn\", \"format_version\": 1,");
  auto r = run_cli("report " + tmp.path().string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(test::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(learn), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(tmp.path() / "report.html"));

  core::write_file_atomic(learn, "{\"format\": \"proprio.learn\", \"format_version\": 1}");
  r = run_cli("report " + tmp.path().string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(learn), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\"complete\" is missing"), std::string::npos) << r.err;

  test::write_learn_run_fixture(tmp.path());
  // Outputs that are inputs are refused before any work, the input untouched.
  for (const std::string& args :
       {" --json " + learn, " --out " + learn, " --json " + (tmp.path() / "report.html").string(),
        " --json " + (tmp.path() / "pushes" / "push_001" / "map.png").string(),
        " --out " + (tmp.path() / "pushes.html").string()}) {
    r = run_cli("report " + tmp.path().string() + args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(test::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--"), std::string::npos) << r.err;
  }
  EXPECT_EQ(core::read_json(learn)["format"], "proprio.learn");
  EXPECT_FALSE(fs::exists(tmp.path() / "report.html"));

  r = run_cli("report " + (tmp.path() / "nowhere").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("nowhere"), std::string::npos) << r.err;
  EXPECT_EQ(run_cli("report").code, 2);  // the directory is required
}

}  // namespace
}  // namespace proprio
