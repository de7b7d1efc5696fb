#include "proprio/core/fields.hpp"

#include <fmt/format.h>

namespace proprio::core {

std::string Bounds::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && max == std::numeric_limits<double>::max()) {
    return fmt::format("finite, {} {}", min_exclusive ? ">" : ">=", min);
  }
  if (has_min && has_max) {
    return fmt::format("in {}{}, {}]", min_exclusive ? "(" : "[", min, max);
  }
  if (has_min) return fmt::format("{} {}", min_exclusive ? ">" : ">=", min);
  if (has_max) return fmt::format("<= {}", max);
  return {};
}

}  // namespace proprio::core
