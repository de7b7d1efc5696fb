// proprio experiment clutter's flags: bad input is one line naming the flag and exit 2, with
// nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>

#include "../support/temp_dir.hpp"
#include "cli_run.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using proprio::test::run_cli;

TEST(ClutterCli, BadInputIsOneLineAndExit2) {
  const test::TempDir temp("proprio_clutter_cli");
  const std::string cache = " --cache " + (temp.path() / "cache").string();
  const struct {
    std::string args;
    std::string message;
  } cases[] = {
      {cache + " --fractions 0.5,1.2", "--fractions"},
      {cache + " --fractions 0", "--fractions"},
      {cache + " --fractions 0.5,abc", "--fractions"},
      {cache + " --topics 1,4", "--topics"},
      {cache + " --topics 4,4", "--topics"},
      {cache + " --seeds 1,1", "--seeds"},
      {cache + " --trials 0", "--trials"},
      {cache + " --pushes 101", "--pushes"},
      {cache + " --words 1", "--words"},
      {cache + " --held-out 0", "--held-out"},
      {cache + " --min-shift 0.2 --max-shift 0.1", "--max-shift"},
      {cache + " --objects book,unicorn", "unicorn"},
      {cache + " --objects book,cd --clutter cd", "repeated"},
      {cache + " --background stripes", "--background"},
      {cache + " --segmentation fancy", "--segmentation"},
      {cache + " --attempts 0", "--attempts"},
      {cache + " --attempts 21", "--attempts"},
      {cache + " --sweep-margin -0.01", "--sweep-margin"},
      {cache + " --sweep-margin 0.5", "--sweep-margin"},
      {cache + " --depth-split -1", "--depth-split"},
      {cache + " --depth-split abc", "--depth-split"},
      {cache + " --erode -1", "--erode"},
      {cache + " --erode 51", "--erode"},
      {cache + " --mot-classifier fancy", "--mot-classifier"},
      {cache + " --mot-word-weight -0.1", "--mot-word-weight"},
      {cache + " --mot-word-weight 1.5", "--mot-word-weight"},
      {"", "--cache"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli("experiment clutter -q" + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(temp.path() / "cache")) << c.args;
  }
}

}  // namespace
}  // namespace proprio::app
