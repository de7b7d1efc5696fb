// Copies of a kernel per instruction set: each has its lane count and gives the same answer, and
// the processor's choice is one it runs.
#include "proprio/core/instruction_sets.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace proprio::core::lanes_test {
#define PROPRIO_KERNEL_FILE "lanes_kernel.inc"
#include "proprio/core/per_instruction_set.inc"
#undef PROPRIO_KERNEL_FILE
}  // namespace proprio::core::lanes_test

namespace proprio::core {
namespace {

TEST(InstructionSets, NamesAndSupport) {
  EXPECT_STREQ(to_string(InstructionSet::kGeneric), "generic");
  EXPECT_STREQ(to_string(InstructionSet::kAvx2), "avx2");
  EXPECT_STREQ(to_string(InstructionSet::kAvx512), "avx512");
  EXPECT_TRUE(cpu_supports(InstructionSet::kGeneric));
  // AVX-512 copies use AVX2 + FMA as well.
  if (cpu_supports(InstructionSet::kAvx512)) {
    EXPECT_TRUE(cpu_supports(InstructionSet::kAvx2));
  }
  const InstructionSet best = best_instruction_set();
  EXPECT_TRUE(cpu_supports(best));
  if (cpu_supports(InstructionSet::kAvx2)) {
    EXPECT_NE(best, InstructionSet::kGeneric);
  }
}

TEST(InstructionSets, EveryCopyTheProcessorRunsAgrees) {
  std::vector<float> x(37);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(i % 5);  // sum 7 * 10 + 0 + 1
  const int n = static_cast<int>(x.size());
  EXPECT_EQ(lanes_test::generic::lanes(), 4);
  EXPECT_EQ(lanes_test::generic::sum(x.data(), n), 71.0f);
#ifdef PROPRIO_X86_COPIES
  if (cpu_supports(InstructionSet::kAvx2)) {
    EXPECT_EQ(lanes_test::avx2::lanes(), 8);
    EXPECT_EQ(lanes_test::avx2::sum(x.data(), n), 71.0f);
  }
  if (cpu_supports(InstructionSet::kAvx512)) {
    EXPECT_EQ(lanes_test::avx512::lanes(), 16);
    EXPECT_EQ(lanes_test::avx512::sum(x.data(), n), 71.0f);
  }
#endif
}

}  // namespace
}  // namespace proprio::core
