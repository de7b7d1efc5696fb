// `--overwrite` of push, selfsupervise and learn (issue 16): the new run is written under a hidden
// name beside --out and swapped in whole, so none of an older run's files stay in the new one, and
// a run killed half-way (SIGKILL once its staging directory exists) leaves the older run as it
// was; the next run that writes there removes the killed run's staging directory.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>
#include <vector>

#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model_io.hpp"

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

std::vector<std::string> split_args(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ' ') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

// Starts `proprio args`, kills it with SIGKILL as soon as a staging directory in `parent` holds
// something (or after 60 s), reaps it; true when it was killed rather than finished.
bool run_and_kill_once_staging(const std::string& args, const fs::path& parent) {
  std::vector<std::string> argv_s = split_args(args);
  argv_s.insert(argv_s.begin(), test::cli_path());
  std::vector<char*> argv;
  argv.reserve(argv_s.size() + 1);
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t child = ::fork();
  if (child == 0) {
    const int null = ::open("/dev/null", O_WRONLY);  // NOLINT(cppcoreguidelines-pro-type-vararg)
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (!staging_started(parent)) {
    if (::waitpid(child, &status, WNOHANG) == child) return false;
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(60)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ::kill(child, SIGKILL);
  ::waitpid(child, &status, 0);
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
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
    const cv::Mat img =
        cv::imread(std::string(PROPRIO_OPENCV_SAMPLES) + "/fruits.jpg", cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    const features::Features f = features::dense_sift(img);
    features::KmeansOptions k;
    k.words = 24;
    k.threads = 1;
    const features::Vocabulary v = features::build_vocabulary(f.descriptors, k).vocabulary;
    features::write_vocabulary(dir() / "v.vocab", v,
                               core::Provenance::current({"overwrite_cli_test"}, 1));
    const std::vector<std::int32_t> words = features::bag_of_words(v, f.descriptors);
    topics::Corpus corpus(v.size());
    for (std::size_t b = 0; b + 50 <= words.size(); b += 50) {
      corpus.add_tokens(std::vector<std::int32_t>(words.begin() + static_cast<long>(b),
                                                  words.begin() + static_cast<long>(b + 50)));
    }
    topics::BatchLdaOptions lo;
    lo.num_topics = 3;
    lo.max_iterations = 10;
    topics::save_lda_model(topics::train_batch_lda(corpus, lo).model, dir() / "m.lda");
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
