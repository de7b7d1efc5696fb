#pragma once
// Runs the built proprio CLI for tests and captures its exit code, stdout and stderr.

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

/// Number of lines in s (a trailing newline does not start a line).
inline int line_count(const std::string& s) {
  int n = 0;
  for (char c : s) n += (c == '\n');
  if (!s.empty() && s.back() != '\n') ++n;
  return n;
}

}  // namespace proprio::test
