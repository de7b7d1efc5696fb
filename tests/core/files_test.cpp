#include "proprio/core/files.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace {
namespace fs = std::filesystem;

class FilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("proprio_files_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(FilesTest, AtomicWriteRoundTripsAndLeavesNoTemporary) {
  const fs::path p = dir_ / "sub" / "a.txt";
  write_file_atomic(p, std::string("hello\0world", 11));
  EXPECT_EQ(read_file(p), std::string("hello\0world", 11));
  write_file_atomic(p, "second");
  EXPECT_EQ(read_file(p), "second");
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_ / "sub")) ++n;
  EXPECT_EQ(n, 1);
}

TEST_F(FilesTest, ReadMissingNamesTheFile) {
  try {
    read_file(dir_ / "nope.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "nope.txt").string() + ": no such file");
  }
  EXPECT_THROW(read_file(dir_), Error);
}

TEST_F(FilesTest, StagedDirectoryAppearsOnlyOnCommit) {
  const fs::path out = dir_ / "episode";
  {
    StagedDirectory staged(out);
    write_file_atomic(staged.staging_path() / "x.txt", "1");
    EXPECT_FALSE(fs::exists(out));
  }  // destroyed without commit: an interrupted writer
  EXPECT_FALSE(fs::exists(out));
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
  EXPECT_EQ(n, 0) << "the staging directory was left behind";

  StagedDirectory staged(out);
  write_file_atomic(staged.staging_path() / "x.txt", "2");
  staged.commit();
  EXPECT_EQ(read_file(out / "x.txt"), "2");
}

TEST_F(FilesTest, StagedDirectoryRefusesNonEmptyUnlessOverwrite) {
  const fs::path out = dir_ / "ep";
  fs::create_directories(out);
  write_file_atomic(out / "old.txt", "old");
  EXPECT_THROW(StagedDirectory{out}, Error);
  StagedDirectory staged(out, /*overwrite=*/true);
  write_file_atomic(staged.staging_path() / "new.txt", "new");
  staged.commit();
  EXPECT_FALSE(fs::exists(out / "old.txt"));
  EXPECT_TRUE(fs::exists(out / "new.txt"));
}

}  // namespace
}  // namespace proprio::core
