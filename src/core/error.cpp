#include "proprio/core/error.hpp"

namespace proprio {

Error Error::in_file(const std::filesystem::path& file, const std::string& problem) {
  return Error(file.string() + ": " + problem);
}

Error Error::at_line(const std::filesystem::path& file, long line, const std::string& problem) {
  return Error(file.string() + ":" + std::to_string(line) + ": " + problem);
}

}  // namespace proprio
