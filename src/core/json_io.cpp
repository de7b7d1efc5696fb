#include "proprio/core/json_io.hpp"

#include <algorithm>

#include "proprio/core/files.hpp"

namespace proprio::core {

Json read_json(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    const size_t byte = std::min<size_t>(e.byte, text.size());
    const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(byte), '\n');
    std::string what = e.what();
    // nlohmann's message starts "[json.exception.parse_error.101] parse error at line ...".
    const auto colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw Error::at_line(path, line, "invalid JSON: " + what);
  }
}

void write_json_atomic(const std::filesystem::path& path, const Json& value) {
  write_file_atomic(path, value.dump(2) + "\n");
}

}  // namespace proprio::core
