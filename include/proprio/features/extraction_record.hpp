#pragma once
// The extraction options as the records of `vocab build` and `vocab quantize` write them.

#include "proprio/core/fields.hpp"
#include "proprio/features/extraction.hpp"

namespace proprio::features {

/// Every described extraction option, and "dense" (whether the features are dense), as those
/// records have always held it.
struct ExtractionRecord {
  ExtractOptions options;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    ExtractOptions::describe(self.options, v);
    v(self.options.kind == FeatureKind::kDense, {"dense", "Whether the features are dense"});
  }
};

}  // namespace proprio::features
