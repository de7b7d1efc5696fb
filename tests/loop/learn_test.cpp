// proprio learn's options: defaults from the issue, --quick, and bad input (the sim run itself
// is exercised by tests/app/learn_cli_test.cpp).
#include "proprio/loop/learn.hpp"

#include <gtest/gtest.h>

#include "proprio/core/error.hpp"

namespace proprio::loop {
namespace {

TEST(Learn, DefaultsAreTheIssuesWorld) {
  const LearnOptions o;
  EXPECT_EQ(o.objects, "book,bottle,cd,giraffe");
  EXPECT_EQ(o.background, "plain");
  EXPECT_EQ(o.seed, 1U);
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(o.resolved().pushes, o.pushes);  // not quick: unchanged
}

TEST(Learn, QuickMakesTheRunSmall) {
  LearnOptions o;
  o.quick = true;
  const LearnOptions q = o.resolved();
  EXPECT_LT(q.pushes, o.pushes);
  EXPECT_LT(q.width, o.width);
  EXPECT_LT(q.words, o.words);
  o.pushes = 5;  // given explicitly: kept
  EXPECT_EQ(o.resolved().pushes, 5);
}

TEST(Learn, BadOptionsThrow) {
  LearnOptions o;
  o.background = "moving";
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.clutter = "book";
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.pushes = 0;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.objects = "book,,cd";
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.clutter = "";
  EXPECT_NO_THROW(o.validate());
}

TEST(Learn, AnExistingOutIsRefusedWithoutOverwrite) {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("proprio_learn_test_" + std::to_string(getpid()));
  fs::create_directories(d);
  LearnOptions o;
  o.out = d;
  o.progress = false;
  try {
    (void)run_learn(o, core::Provenance::current({"learn_test"}, 1));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("already exists"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(d));
  fs::remove_all(d);
}

}  // namespace
}  // namespace proprio::loop
