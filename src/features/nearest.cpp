// One copy of nearest.inc per instruction set (core/per_instruction_set.inc), the widest that the
// processor runs chosen once.
//
// Why a hand-written kernel: the work of k-means and quantisation is N x K dot products of
// 128-D vectors. Eigen (built here for the x86-64 baseline, SSE2, because the library must run
// on any x86-64) reaches a fraction of what AVX2/AVX-512 FMA gives, and compiling Eigen twice
// for two targets would break the one-definition rule. The only BLAS installed is the netlib
// reference. A 6 x 2-vector register block with the arg-min fused in is all that is needed.

#include "nearest.hpp"

#include <cassert>

#include "proprio/core/instruction_sets.hpp"

namespace proprio::features::detail {

#define PROPRIO_KERNEL_FILE "nearest.inc"
#include "proprio/core/per_instruction_set.inc"
#undef PROPRIO_KERNEL_FILE

namespace {

constexpr float kHuge = 1e30F;

using Kernel = void (*)(const float*, long, int, const float*, const float*, int, float, int*,
                        float*, float*);

using Distances = void (*)(const float*, long, int, const float*, float*);

struct Choice {
  const char* name;
  int lanes;
  Kernel kernel;
  Distances distances;
};

const Choice& choice() {
  static const Choice kChosen = []() -> Choice {
#ifdef PROPRIO_X86_COPIES
    using core::InstructionSet;
    const InstructionSet set = core::best_instruction_set();
    if (set == InstructionSet::kAvx512) {
      return {"avx512", 16, avx512::nearest, avx512::sq_distances};
    }
    if (set == InstructionSet::kAvx2) return {"avx2", 8, avx2::nearest, avx2::sq_distances};
#endif
    return {"generic", 4, generic::nearest, generic::sq_distances};
  }();
  return kChosen;
}

}  // namespace

PackedCentres pack_centres(const float* centres, int count, int dimension) {
  assert(count > 0 && dimension > 0);
  PackedCentres p;
  p.count = count;
  p.dimension = dimension;
  p.panel = 2 * choice().lanes;
  const int panels = (count + p.panel - 1) / p.panel;
  p.data.assign(static_cast<std::size_t>(panels) * dimension * p.panel, 0.0F);
  p.half_norms.assign(static_cast<std::size_t>(panels) * p.panel, kHuge);
  for (int k = 0; k < count; ++k) {
    const float* c = centres + static_cast<std::size_t>(k) * dimension;
    float* panel = p.data.data() + static_cast<std::size_t>(k / p.panel) * dimension * p.panel;
    double norm = 0;
    for (int d = 0; d < dimension; ++d) {
      panel[static_cast<std::size_t>(d) * p.panel + k % p.panel] = c[d];
      norm += static_cast<double>(c[d]) * c[d];
    }
    p.half_norms[static_cast<std::size_t>(k)] = static_cast<float>(norm / 2);
  }
  return p;
}

void nearest_centres(const float* points, std::size_t n, const PackedCentres& centres, int* best,
                     float* best_sq, float* second_sq) {
  if (n == 0) return;
  const Choice& c = choice();
  assert(centres.panel == 2 * c.lanes);
  const int panels = static_cast<int>(centres.half_norms.size()) / centres.panel;
  c.kernel(points, static_cast<long>(n), centres.dimension, centres.data.data(),
           centres.half_norms.data(), panels, kHuge, best, best_sq, second_sq);
}

void squared_distances(const float* points, std::size_t n, int dimension, const float* centre,
                       float* out) {
  choice().distances(points, static_cast<long>(n), dimension, centre, out);
}

std::string nearest_kernel_name() { return choice().name; }

}  // namespace proprio::features::detail
