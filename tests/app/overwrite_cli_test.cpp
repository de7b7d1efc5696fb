// `--overwrite` of push, selfsupervise and learn (issue 16): the new run is written under a hidden
// name beside --out and swapped in whole, so none of an older run's files stay in the new one, and
// a run killed half-way (SIGKILL once its staging directory exists) leaves the older run as it
// was; the next run that writes there removes the killed run's staging directory.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "tiny_models.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using proprio::test::run_cli;

constexpr const char* kStale = "stale_from_an_older_run.txt";
constexpr const char* kOld = "an older run\n";

// The hidden entries of `dir` (staging directories and temporary files of writers).
std::vector<std::string> hidden_entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (!name.empty() && name[0] == '.') out.push_back(name);
  }
  return out;
}

// A hidden staging directory in `dir` that holds something (the run has started writing).
bool staging_started(const fs::path& dir) {
  for (const std::string& name : hidden_entries(dir)) {
    std::error_code ec;
    if (fs::is_directory(dir / name, ec) && !fs::is_empty(dir / name, ec)) return true;
  }
  return false;
}

// Starts `proprio args`, kills it with SIGKILL as soon as a staging directory in `parent` holds
// something (or after 60 s), reaps it; true when it was killed rather than finished.
bool run_and_kill_once_staging(const std::string& args, const fs::path& parent) {
  return test::run_cli_and_kill(
      args, [&] { return staging_started(parent); }, std::chrono::milliseconds(0),
      std::chrono::seconds(60));
}

// An older run at parent/run: its marker file (what the command leaves there) and a file the
// new run does not write. Then a run killed half-way, then a whole run, both with --overwrite.
void expect_replaced_whole(const std::string& command, const fs::path& parent,
                           const std::string& marker) {
  const fs::path run = parent / "run";
  core::write_file_atomic(run / marker, kOld);
  core::write_file_atomic(run / kStale, kOld);
  const std::string args = command + " --out " + run.string() + " --overwrite";

  EXPECT_TRUE(run_and_kill_once_staging(args, parent)) << "the run ended before it was killed";
  // Killed half-way: the older run is whole at the path.
  EXPECT_EQ(core::read_file(run / marker), kOld);
  EXPECT_TRUE(fs::exists(run / kStale)) << "the killed run removed the older run";

  const auto r = run_cli(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(run / kStale)) << "a file of the older run stayed in the new one";
  EXPECT_NE(core::read_file(run / marker), kOld);
  // The killed run's staging directory was removed by the next run that wrote there.
  EXPECT_TRUE(hidden_entries(parent).empty()) << hidden_entries(parent).front();
}

class OverwriteCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(dir());
    fs::create_directories(dir());
    test::write_tiny_vocabulary_and_model(dir(), "overwrite_cli_test");
  }
  static void TearDownTestSuite() { fs::remove_all(dir()); }
  static const fs::path& dir() {
    static const fs::path kDir =
        fs::temp_directory_path() / ("proprio_overwrite_cli_" + std::to_string(getpid()));
    return kDir;
  }
};

TEST_F(OverwriteCli, PushReplacesTheOlderRunWholeAndAKilledPushLeavesIt) {
  const test::TempDir parent("proprio_overwrite_push_");
  expect_replaced_whole(
      "push --objects 5 --seed 6 --object bike --target-x 0.205 --target-y 0.017 --max-pushes 1 "
      "--fps 5 --width 320 --height 240",
      parent.path(), "push.json");
}

TEST_F(OverwriteCli, SelfsuperviseReplacesTheOlderRunWholeAndAKilledRunLeavesIt) {
  const test::TempDir parent("proprio_overwrite_selfsup_");
  expect_replaced_whole(
      "selfsupervise --objects book,bottle --pushes 1 --clear-pushes 1 --views blob --held-out 3 "
      "--width 160 --height 120 --step 4 --min-features 3 --seed 3 -q --model " +
          (dir() / "m.lda").string() + " --vocabulary " + (dir() / "v.vocab").string(),
      parent.path(), "selfsupervise.json");
}

TEST_F(OverwriteCli, LearnReplacesTheOlderRunWholeAndAKilledRunLeavesIt) {
  const test::TempDir parent("proprio_overwrite_learn_");
  expect_replaced_whole(
      "learn --objects book --background plain --pushes 1 --width 160 --height 120 --words 20 "
      "--topics 2 --held-out 2 --min-features 3 --seed 2 -q",
      parent.path(), "learn.json");
}

}  // namespace
}  // namespace proprio::app
