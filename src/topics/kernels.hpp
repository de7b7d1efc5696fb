#pragma once
// The hot loops of the E-step, compiled for several instruction sets and chosen at run time
// (kernels.cpp). Everything here works in single precision on rows of `stride` floats, stride a
// multiple of the kernel's lane count; lanes beyond the K topics are kept at zero.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace proprio::topics::detail {

/// exp(E[log .]) below exp(kLogFloor) is stored as exp(kLogFloor): the terms it drops are below
/// 1e-13 of a document's normaliser, and products of two stay clear of denormal floats.
inline constexpr float kLogFloor = -30.0f;

struct DocEStepArgs {
  const std::int32_t* ids = nullptr;  ///< n row indices into beta
  const float* counts = nullptr;      ///< n counts
  int n = 0;
  const float* beta = nullptr;  ///< exp(E[log beta]) rows (eq B.19), `stride` floats each
  int num_topics = 0;
  int stride = 0;
  float alpha = 0.0f;
  int max_iterations = 100;
  float tolerance = 1e-3f;
  float* gamma = nullptr;           ///< stride floats: in, the start (K values); out, the result
  float* exp_elog_theta = nullptr;  ///< stride floats, out: exp(E[log theta]) (eq B.18)
  float* weights = nullptr;  ///< n floats, out: counts_j / sum_k exp(Elog theta_k + Elog beta_kj)
  float* scratch = nullptr;  ///< stride floats
};

struct DocEStepOut {
  int iterations = 0;
  bool converged = false;
  double log_norm = 0.0;  ///< sum_j counts_j log(sum_k exp(E[log theta_k] + E[log beta_kj]))
};

struct Kernels {
  const char* name;
  int lanes;
  /// One document's E-step (eq B.16-B.18), phi kept implicit.
  DocEStepOut (*estep_doc)(const DocEStepArgs& args);
  /// out_i = exp(max(psi(x_i) - sub_i, kLogFloor)), n a multiple of lanes, x_i > 0.
  void (*exp_digamma_minus)(const float* x, const float* sub, float* out, int n);
  /// y += a x, n a multiple of lanes.
  void (*axpy)(float a, const float* x, float* y, int n);
  /// psi(x) for a single x > 0, with the same code as the vector paths (for tests).
  float (*digamma)(float x);
};

/// The fastest kernels this processor runs, or those named by PROPRIO_TOPICS_KERNEL.
const Kernels& best_kernels();
/// Kernels by name ("generic", "avx2", "avx512"); throws Error if unknown or unsupported here.
const Kernels& kernels_named(std::string_view name);
/// Names of the kernels this processor supports.
std::vector<std::string> supported_kernels();

}  // namespace proprio::topics::detail
