#include "proprio/core/data_dir.hpp"

#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace fs = std::filesystem;

namespace {

bool holds_data(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "models", ec);
}

}  // namespace

fs::path data_directory() {
  const char* env = std::getenv("PROPRIO_DATA_DIR");
  if (env != nullptr && env[0] != '\0') {
    fs::path dir(env);
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
      throw Error::in_file(dir, "PROPRIO_DATA_DIR is not a directory");
    return dir;
  }
  std::vector<fs::path> tried;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    fs::path beside = (exe.parent_path() / ".." / "share" / "proprio").lexically_normal();
    if (holds_data(beside)) return beside;
    tried.push_back(beside);
  }
  fs::path installed(PROPRIO_INSTALL_DATA_DIR);
  if (holds_data(installed)) return installed;
  tried.push_back(installed);
  std::string where;
  for (const fs::path& p : tried) where += (where.empty() ? "" : ", ") + p.string();
  throw Error("proprio's data directory (models/, objects/) was not found in " + where +
              "; set PROPRIO_DATA_DIR to it");
}

}  // namespace proprio::core
