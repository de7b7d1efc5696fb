#pragma once
// Bytes written as hexadecimal text, for tests that pin a file format to known bytes.

#include <string>
#include <string_view>

namespace proprio::test {

/// "50520a" -> "PR\n". `hex` has an even number of hexadecimal digits.
inline std::string bytes_from_hex(std::string_view hex) {
  std::string out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    out += static_cast<char>(std::stoi(std::string(hex.substr(i, 2)), nullptr, 16));
  }
  return out;
}

}  // namespace proprio::test
