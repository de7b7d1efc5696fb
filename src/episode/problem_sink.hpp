#pragma once
// Internal: collects the problems of an episode, or throws the first one (read_episode).

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/episode/check.hpp"

namespace proprio::episode::detail {

class ProblemSink {
 public:
  /// throw_first: add() throws Error at once (read_episode); otherwise problems are collected,
  /// at most max_per_group per group (check_episode).
  ProblemSink(bool throw_first, int max_per_group)
      : throw_first_(throw_first), max_per_group_(max_per_group) {}

  /// "FILE: what" (line 0) or "FILE:LINE: what". `group` (default: the file) bounds how many are
  /// listed, so that 10000 missing frames do not make 10000 lines.
  void add(const std::filesystem::path& file, const std::string& what, long line = 0,
           const std::string& group = {});
  /// An Error already formatted "FILE: ..." by the code that read `file`.
  void add_error(const std::filesystem::path& file, const Error& e);

  [[nodiscard]] bool empty() const { return problems_.empty() && omitted_.empty(); }
  /// The problems, then one "N more problems" entry per group that hit the limit.
  std::vector<Problem> take();

 private:
  void record(const std::filesystem::path& file, const std::string& message,
              const std::string& group);

  bool throw_first_;
  int max_per_group_;
  std::vector<Problem> problems_;
  std::map<std::string, int> per_group_;
  std::map<std::string, int> omitted_;  ///< group -> problems not listed
};

}  // namespace proprio::episode::detail
