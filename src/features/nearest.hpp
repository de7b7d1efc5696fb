#pragma once
// Nearest-centre search for k-means and quantisation: for every point, the centre with the
// smallest squared Euclidean distance ||x||^2 - 2 x.c + ||c||^2, computed as a register-blocked
// matrix product fused with the arg-min (no N x K distance matrix is stored). One copy of the
// kernel per instruction set (nearest.inc), chosen once from what the processor supports, as in
// src/topics/kernels.cpp.

#include <cstddef>
#include <string>
#include <vector>

namespace proprio::features::detail {

/// Centres packed for the kernel: panels of `panel` centres, each stored dimension-major
/// (for d: for j in panel: c[j][d]), padded with zero centres whose half-norm is +huge.
struct PackedCentres {
  int count = 0;                  ///< K
  int dimension = 0;              ///< D
  int panel = 0;                  ///< centres per panel (2 vector widths)
  std::vector<float> data;        ///< panels * D * panel
  std::vector<float> half_norms;  ///< ||c||^2 / 2, padded to panels * panel
};

/// Packs K x D row-major centres for the chosen kernel.
PackedCentres pack_centres(const float* centres, int count, int dimension);

/// For rows [0, n) of `points` (row-major, `dimension` floats a row): best[i] = index of the
/// nearest centre, best_sq[i] = its squared distance (clamped at 0) and, if second_sq is not
/// null, second_sq[i] = the squared distance to the second nearest (+huge when K = 1).
void nearest_centres(const float* points, std::size_t n, const PackedCentres& centres, int* best,
                     float* best_sq, float* second_sq);

/// out[i] = squared distance of row i of `points` (n x dimension) to `centre`.
void squared_distances(const float* points, std::size_t n, int dimension, const float* centre,
                       float* out);

/// The name of the kernel in use ("generic", "avx2", "avx512").
std::string nearest_kernel_name();

}  // namespace proprio::features::detail
