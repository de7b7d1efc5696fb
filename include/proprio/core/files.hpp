#pragma once
// Whole-file reading and atomic writing. Result files are written to a temporary name beside the
// target and renamed over it, so that a reader never sees a half-written file.

#include <filesystem>
#include <string>
#include <string_view>

namespace proprio::core {

/// Reads a whole file. Throws Error naming the file when it is missing or unreadable.
std::string read_file(const std::filesystem::path& path);

/// Writes `contents` to `path` atomically (temporary file in the same directory, flushed, renamed).
/// Creates missing parent directories. Throws Error naming the file on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

/// A directory that is built under a temporary name and appears at its final path only on
/// commit(). If destroyed before commit(), the temporary directory is removed, so an interrupted
/// writer leaves nothing behind that could be read as a finished result.
class StagedDirectory {
 public:
  /// Stages `final_path`. Throws Error if `final_path` exists and is not an empty directory,
  /// unless `overwrite` is set (then the old directory is replaced on commit()).
  explicit StagedDirectory(std::filesystem::path final_path, bool overwrite = false);
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  ~StagedDirectory();

  /// Where to write the contents until commit().
  [[nodiscard]] const std::filesystem::path& staging_path() const { return staging_; }
  [[nodiscard]] const std::filesystem::path& final_path() const { return final_; }

  /// Renames the staging directory to its final path.
  void commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path staging_;
  bool overwrite_;
  bool committed_ = false;
};

}  // namespace proprio::core
