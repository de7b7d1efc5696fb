#pragma once
// Runs the built proprio CLI for tests and captures its exit code, stdout and stderr.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../support/paths.hpp"

namespace proprio::test {

struct CliResult {
  int code = -1;
  std::string out;
  std::string err;
};

/// Runs `proprio args` (the built CLI) through the shell (args are shell text).
inline CliResult run_cli(const std::string& args) {
  namespace fs = std::filesystem;
  static int counter = 0;
  const fs::path dir = fs::temp_directory_path();
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const fs::path out = dir / ("proprio_cli_out_" + tag);
  const fs::path err = dir / ("proprio_cli_err_" + tag);
  std::string cmd = cli_path();
  cmd += " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

/// Splits shell-free arguments on spaces (the paths of the tests that use it have none).
inline std::vector<std::string> split_args(const std::string& args) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : args) {
    if (c == ' ') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

/// Starts `proprio args` (split_args, no shell) as a child whose output goes to /dev/null, polls
/// `ready()` every millisecond (at most `timeout`), waits `delay` more, then kills the child with
/// SIGKILL and reaps it. True when the kill ended it; false when it had ended by itself first.
inline bool run_cli_and_kill(const std::string& args, const std::function<bool()>& ready,
                             std::chrono::milliseconds delay, std::chrono::seconds timeout) {
  std::vector<std::string> argv_s = split_args(args);
  argv_s.insert(argv_s.begin(), cli_path());
  std::vector<char*> argv;
  argv.reserve(argv_s.size() + 1);
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t child = ::fork();
  if (child == 0) {
    const int null = ::open("/dev/null", O_WRONLY);  // NOLINT(cppcoreguidelines-pro-type-vararg)
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (!ready()) {
    if (::waitpid(child, &status, WNOHANG) == child) return false;
    if (std::chrono::steady_clock::now() - t0 > timeout) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  std::this_thread::sleep_for(delay);
  ::kill(child, SIGKILL);
  ::waitpid(child, &status, 0);
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

/// Number of lines in s (a trailing newline does not start a line).
inline int line_count(const std::string& s) {
  int n = 0;
  for (char c : s) n += (c == '\n');
  if (!s.empty() && s.back() != '\n') ++n;
  return n;
}

}  // namespace proprio::test
