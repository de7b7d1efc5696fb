#include "proprio/core/instruction_sets.hpp"

#include <initializer_list>

namespace proprio::core {

const char* to_string(InstructionSet set) {
  switch (set) {
    case InstructionSet::kAvx2:
      return "avx2";
    case InstructionSet::kAvx512:
      return "avx512";
    case InstructionSet::kGeneric:
      break;
  }
  return "generic";
}

bool cpu_supports(InstructionSet set) {
#if defined(__x86_64__) && defined(__GNUC__)
  // The same features as the `#pragma GCC target` lines of per_instruction_set.inc.
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  switch (set) {
    case InstructionSet::kGeneric:
      return true;
    case InstructionSet::kAvx2:
      return avx2;
    case InstructionSet::kAvx512:
      return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq");
  }
  return false;
#else
  return set == InstructionSet::kGeneric;
#endif
}

InstructionSet best_instruction_set() {
  for (const InstructionSet s : {InstructionSet::kAvx512, InstructionSet::kAvx2}) {
    if (cpu_supports(s)) return s;
  }
  return InstructionSet::kGeneric;
}

}  // namespace proprio::core
