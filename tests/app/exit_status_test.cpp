// The CLI's exit statuses under main()'s own mapping (app/exit_status.cpp): a broken invariant of
// the library is a bug (exit 1, "internal error"), bad outside input is exit 2; one line each.
#include "exit_status.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/planning/push_planner.hpp"

namespace proprio {
namespace {

// Death tests run the call in a child process and check how it ends, as the shell would see the
// CLI end.
TEST(ExitStatusDeathTest, ABrokenLibraryInvariantExitsOneAsAnInternalError) {
  // density_of_others of a putative object the view does not have: the caller's bug, which no
  // file or option reaches (issue 14's require() audit made it an ensure()).
  const planning::PlanningView empty;
  EXPECT_EXIT(std::exit(app::run_with_exit_status([&] {
                (void)planning::density_of_others(empty, 0);
                return 0;
              })),
              testing::ExitedWithCode(1),
              "^proprio: internal error: density of others: no putative object 0\n$");
}

TEST(ExitStatusDeathTest, BadInputExitsTwoWithOneLineNamingTheFile) {
  EXPECT_EXIT(std::exit(app::run_with_exit_status([] {
                (void)core::read_file("no/such/input.csv");
                return 0;
              })),
              testing::ExitedWithCode(2), "^proprio: no/such/input.csv: no such file\n$");
}

TEST(ExitStatus, TheBodysOwnStatusPassesThrough) {
  EXPECT_EQ(app::run_with_exit_status([] { return 0; }), 0);
  EXPECT_EQ(app::run_with_exit_status([] { return 3; }), 3);
  EXPECT_EQ(app::run_with_exit_status([]() -> int { throw InternalError("x"); }), 1);
  EXPECT_EQ(app::run_with_exit_status([]() -> int { throw Error("x"); }), 2);
}

}  // namespace
}  // namespace proprio
