#pragma once
// Whole-file reading and atomic writing. Result files are written to a temporary name beside the
// target and renamed over it, so that a reader never sees a half-written file.
//
// Every reader of outside files goes through read_file (or read_file_head): the file is opened
// without blocking and must be a regular file, so that a FIFO or a device (/dev/zero) given as an
// input is refused at once instead of hanging or being read for ever; and its size is checked
// against a cap before anything is allocated.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace proprio::core {

/// The largest file read_file reads whole unless told otherwise (1 GiB): no input of proprio's
/// is near it, and a bigger one is refused before its bytes are allocated.
inline constexpr std::uintmax_t kMaxReadBytes = std::uintmax_t{1} << 30;

/// Reads a whole regular file of at most `max_bytes`. Throws Error naming the file when it is
/// missing, unreadable, not a regular file (a FIFO, device, socket or directory) or too big.
std::string read_file(const std::filesystem::path& path, std::uintmax_t max_bytes = kMaxReadBytes);

/// The first `n` bytes of a regular file (all of it when shorter), with read_file's checks.
std::string read_file_head(const std::filesystem::path& path, std::size_t n);

/// The size of a regular file, with read_file's checks (missing, not a regular file).
std::uintmax_t regular_file_size(const std::filesystem::path& path);

/// Writes `contents` to `path` atomically (temporary file in the same directory, flushed, renamed).
/// Creates missing parent directories. Temporary files left beside `path` by a killed writer
/// (one whose process is gone) are removed first. Throws Error naming the file on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

/// Removes the temporary files and staging directories that a killed writer of `path` left
/// beside it (their process is gone); returns how many. Called by every writer.
int remove_stale_temporaries(const std::filesystem::path& path);

/// Throws Error unless `output` is distinct from every input: not the same file or directory
/// (also through symbolic links or hard links) and not a directory holding an input, which
/// replacing it would delete. `option` names the output's option in the message ("--out").
void require_output_not_input(const std::filesystem::path& output,
                              const std::vector<std::filesystem::path>& inputs,
                              std::string_view option);

/// The files whose presence marks a directory as one proprio wrote (an episode, a segmentation,
/// an evaluation, a sweep): only such a directory is replaced by `--overwrite`.
inline constexpr std::string_view kResultMarkers[] = {"episode.json", "segment.json",
                                                      "summary.json", "sweep.json"};

/// A directory that is built under a temporary name and appears at its final path only on
/// commit(). If destroyed before commit(), the temporary directory is removed, so an interrupted
/// writer leaves nothing behind that could be read as a finished result.
class StagedDirectory {
 public:
  /// Stages `final_path`. Throws Error if `final_path` exists and is not an empty directory,
  /// unless `overwrite` is set and it holds one of `markers` (files or relative paths of files:
  /// what the writing command leaves there; then the old directory is replaced on commit()).
  /// Staging directories of killed writers beside it are removed.
  explicit StagedDirectory(std::filesystem::path final_path, bool overwrite = false,
                           std::span<const std::string_view> markers = kResultMarkers);
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  ~StagedDirectory();

  /// Where to write the contents until commit().
  [[nodiscard]] const std::filesystem::path& staging_path() const { return staging_; }
  [[nodiscard]] const std::filesystem::path& final_path() const { return final_; }

  /// Moves the staging directory to its final path. An old directory there is swapped out in
  /// one atomic exchange, so that the path holds the old or the new at every moment.
  void commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path staging_;
  bool overwrite_;
  bool committed_ = false;
};

}  // namespace proprio::core
