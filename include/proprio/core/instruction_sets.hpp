#pragma once
// Hot loops compiled once per x86-64 instruction set and chosen at run time (the features'
// nearest-centre kernel, the topics' E-step). The library is built for the x86-64 baseline (SSE2)
// so that it runs anywhere; a kernel file, written once for PROPRIO_LANES float lanes, is also
// compiled for AVX2 and AVX-512 by including per_instruction_set.inc (beside this header), and
// the widest copy the processor runs is called.

namespace proprio::core {

/// The copies per_instruction_set.inc makes: generic (4 lanes, baseline), avx2 (8 lanes, AVX2 +
/// FMA), avx512 (16 lanes, AVX-512 F, VL and DQ with AVX2 + FMA).
enum class InstructionSet { kGeneric, kAvx2, kAvx512 };

/// "generic", "avx2" or "avx512".
const char* to_string(InstructionSet set);

/// Whether this build has the set's copy and this processor runs it (generic: always).
bool cpu_supports(InstructionSet set);

/// The widest set of cpu_supports.
InstructionSet best_instruction_set();

}  // namespace proprio::core
