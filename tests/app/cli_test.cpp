// The CLI's contract: --help at every level, --version, exit 2 with one line on bad usage.
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

}  // namespace
}  // namespace proprio
