#include "proprio/core/data_dir.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"

namespace proprio::core {
namespace {
namespace fs = std::filesystem;

// Sets PROPRIO_DATA_DIR for one test and puts back what was there.
class DataDirEnv {
 public:
  explicit DataDirEnv(const char* value) {
    if (const char* old = std::getenv("PROPRIO_DATA_DIR")) old_ = old;
    if (value != nullptr) {
      ::setenv("PROPRIO_DATA_DIR", value, 1);
    } else {
      ::unsetenv("PROPRIO_DATA_DIR");
    }
  }
  DataDirEnv(const DataDirEnv&) = delete;
  DataDirEnv& operator=(const DataDirEnv&) = delete;
  ~DataDirEnv() {
    if (old_) {
      ::setenv("PROPRIO_DATA_DIR", old_->c_str(), 1);
    } else {
      ::unsetenv("PROPRIO_DATA_DIR");
    }
  }

 private:
  std::optional<std::string> old_;
};

TEST(DataDirectory, TheEnvironmentComesFirst) {
  const test::TempDir dir("proprio_data_dir_");
  const DataDirEnv env(dir.path().c_str());
  EXPECT_EQ(data_directory(), dir.path());
}

TEST(DataDirectory, AnEnvironmentPathThatIsNoDirectoryIsAnError) {
  const test::TempDir dir("proprio_data_dir_");
  const std::string missing = (dir.path() / "nowhere").string();
  const DataDirEnv env(missing.c_str());
  try {
    (void)data_directory();
    FAIL() << "no Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
}

TEST(DataDirectory, WithoutTheEnvironmentOnlyADirectoryWithModelsCounts) {
  // The test program sits in the build tree's tests/core, where no share/proprio lies beside it:
  // the answer is an installation's data directory (holding models/) or an Error that says
  // what was tried and how to fix it; never a directory without models/.
  const DataDirEnv env(nullptr);
  try {
    const fs::path dir = data_directory();
    EXPECT_TRUE(fs::is_directory(dir / "models")) << dir;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("PROPRIO_DATA_DIR"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("share/proprio"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace proprio::core
