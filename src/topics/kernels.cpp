// One copy of kernels.inc per instruction set (core/per_instruction_set.inc); the processor is
// asked once which copy it can run.

#include "kernels.hpp"

#include <cstdlib>

#include "proprio/core/error.hpp"
#include "proprio/core/instruction_sets.hpp"

namespace proprio::topics::detail {

#define PROPRIO_KERNEL_FILE "kernels.inc"
#include "proprio/core/per_instruction_set.inc"
#undef PROPRIO_KERNEL_FILE

namespace {

const Kernels kGeneric{"generic",          4,
                       generic::estep_doc, generic::exp_digamma_minus,
                       generic::axpy,      generic::digamma_one};
#ifdef PROPRIO_X86_COPIES
const Kernels kAvx2{"avx2",           8, avx2::estep_doc, avx2::exp_digamma_minus, avx2::axpy,
                    avx2::digamma_one};
const Kernels kAvx512{
    "avx512", 16, avx512::estep_doc, avx512::exp_digamma_minus, avx512::axpy, avx512::digamma_one};
#endif

constexpr core::InstructionSet kSets[] = {
    core::InstructionSet::kGeneric, core::InstructionSet::kAvx2, core::InstructionSet::kAvx512};

// The copy for `set`, which cpu_supports.
const Kernels& copy_for(core::InstructionSet set) {
#ifdef PROPRIO_X86_COPIES
  if (set == core::InstructionSet::kAvx512) return kAvx512;
  if (set == core::InstructionSet::kAvx2) return kAvx2;
#endif
  return kGeneric;
}

}  // namespace

std::vector<std::string> supported_kernels() {
  std::vector<std::string> names;
  for (const auto set : kSets) {
    if (core::cpu_supports(set)) names.emplace_back(core::to_string(set));
  }
  return names;
}

const Kernels& kernels_named(std::string_view name) {
  for (const auto set : kSets) {
    if (name == core::to_string(set) && core::cpu_supports(set)) return copy_for(set);
  }
  std::string msg = "LDA kernel '";
  msg += name;
  msg += "' is unknown or not supported by this processor";
  throw Error(msg);
}

const Kernels& best_kernels() {
  static const Kernels& chosen = []() -> const Kernels& {
    if (const char* env = std::getenv("PROPRIO_TOPICS_KERNEL"); env != nullptr && *env != '\0') {
      return kernels_named(env);
    }
    return copy_for(core::best_instruction_set());
  }();
  return chosen;
}

}  // namespace proprio::topics::detail
