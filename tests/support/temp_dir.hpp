#pragma once
// A scratch directory for a test, created empty and removed afterwards.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace proprio::test {

/// A fresh empty directory under the system's temporary directory, removed by the destructor
/// unless `keep` (to look at what a test wrote). Its name is `prefix`, then `tag` or, without
/// one, the running test's suite and name ('/' of parameterised tests as '_'), then '_' and the
/// process id, so that concurrent test programs do not meet.
class TempDir {
 public:
  explicit TempDir(std::string_view prefix, std::string_view tag = {}, bool keep = false)
      : keep_(keep) {
    std::string name(prefix);
    if (!tag.empty()) {
      name += tag;
    } else if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
      name += info->test_suite_name();
      name += '_';
      name += info->name();
    }
    name += '_';
    name += std::to_string(::getpid());
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    if (keep_) return;
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  bool keep_;
};

}  // namespace proprio::test
