#pragma once
// A bound on the nesting of YAML text, checked before a YAML library parses it: OpenCV's
// FileStorage and yaml-cpp parse nested values by recursion, so a few kilobytes of '[' or of
// ever deeper indentation overflow the stack (issue 16).

#include <filesystem>
#include <string_view>

namespace proprio::core {

/// The deepest nesting a YAML input of proprio's may have. Calibration files nest two levels and
/// scene files five or six.
inline constexpr int kMaxYamlDepth = 64;

/// Throws Error "FILE:LINE: nested deeper than N levels" when `text` may nest deeper than
/// `max_depth`. The estimate counts indentation levels, the "- " of sequences started on one
/// line, and flow brackets outside quotes; it may overcount (brackets in a block scalar) but never
/// undercounts what a YAML parser recurses on.
void check_yaml_depth(std::string_view text, const std::filesystem::path& source,
                      int max_depth = kMaxYamlDepth);

/// Throws Error "FILE:LINE: not UTF-8 text" unless `text` is well-formed UTF-8. YAML is UTF-8
/// text; a stray byte would otherwise reach a JSON value and fail when it is written.
void check_utf8(std::string_view text, const std::filesystem::path& source);

/// Whether `text` is well-formed UTF-8 (for strings a parser made, which have no line).
[[nodiscard]] bool is_utf8(std::string_view text);

}  // namespace proprio::core
