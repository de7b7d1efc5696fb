#include "problem_sink.hpp"

namespace proprio::episode::detail {

void ProblemSink::add(const std::filesystem::path& file, const std::string& what, long line,
                      const std::string& group) {
  const Error e = line > 0 ? Error::at_line(file, line, what) : Error::in_file(file, what);
  record(file, e.what(), group.empty() ? file.string() : group);
}

void ProblemSink::add_error(const std::filesystem::path& file, const Error& e) {
  record(file, e.what(), file.string());
}

void ProblemSink::record(const std::filesystem::path& file, const std::string& message,
                         const std::string& group) {
  if (throw_first_) throw Error(message);
  int& n = per_group_[group];
  if (n < max_per_group_) {
    problems_.push_back({file, message});
  } else {
    ++omitted_[group];
  }
  ++n;
}

std::vector<Problem> ProblemSink::take() {
  for (const auto& [group, count] : omitted_) {
    std::string m = group;
    m += ": ";
    m += std::to_string(count);
    m += " more problem";
    m += count == 1 ? "" : "s";
    m += " not listed";
    problems_.push_back({std::filesystem::path(group), m});
  }
  omitted_.clear();
  return std::move(problems_);
}

}  // namespace proprio::episode::detail
