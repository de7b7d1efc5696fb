// The CLI's contract: --help at every level, --version, exit 2 with one line on bad usage and on
// bad input (a broken invariant is exit 1: tests/app/exit_status_test.cpp).
#include <gtest/gtest.h>

#include "cli_run.hpp"
#include "proprio/core/version.hpp"

namespace proprio {
namespace {
using test::line_count;
using test::run_cli;

TEST(Cli, VersionNamesVersionAndCommit) {
  const auto r = run_cli("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find(std::string("proprio ") + kVersion), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(kGitCommit), std::string::npos);
}

TEST(Cli, HelpAtEveryLevel) {
  for (const char* args : {"--help", "calib --help", "episode --help"}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.code, 0) << args;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << args << ": " << r.out;
  }
}

TEST(Cli, BadUsageIsOneLineAndExitTwo) {
  for (const char* args : {"", "no-such-verb", "calib", "--no-such-flag"}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.code, 2) << "'" << args << "'";
    EXPECT_EQ(line_count(r.err), 1) << "'" << args << "': " << r.err;
    EXPECT_EQ(r.err.rfind("proprio: ", 0), 0u) << r.err;
  }
}

// Bad input (a missing or corrupt file) is proprio::Error: one line naming the file, exit 2, and
// never reported as an internal error (issue 14's require() audit kept these as input checks).
TEST(Cli, BadInputIsOneLineNamingTheFileAndExitTwo) {
  const std::string not_a_model = (test::source_dir() / "README.md").string();
  for (const std::string& args :
       {std::string("episode info no/such/episode"), std::string("lda topics --model no/such.lda"),
        "lda topics --model " + not_a_model}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("proprio: ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_TRUE(r.err.find("no/such") != std::string::npos ||
                r.err.find("README.md") != std::string::npos)
        << r.err;
  }
}

}  // namespace
}  // namespace proprio
