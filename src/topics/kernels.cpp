// One copy of kernels.inc per instruction set. The AVX copies live inside `#pragma GCC target`
// regions and call nothing outside them, so no AVX code can leak into the generic path; the
// processor is asked once which copy it can run.

#include "kernels.hpp"

#include <cstdlib>

#include "proprio/core/error.hpp"

namespace proprio::topics::detail {

namespace generic {
#define PROPRIO_LANES 4
#include "kernels.inc"
#undef PROPRIO_LANES
}  // namespace generic

#if defined(__x86_64__) && defined(__GNUC__)
#define PROPRIO_TOPICS_X86 1
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
#define PROPRIO_LANES 8
#include "kernels.inc"
#undef PROPRIO_LANES
}  // namespace avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq,avx2,fma")
namespace avx512 {
#define PROPRIO_LANES 16
#include "kernels.inc"
#undef PROPRIO_LANES
}  // namespace avx512
#pragma GCC pop_options
#endif

namespace {

const Kernels kGeneric{"generic",          4,
                       generic::estep_doc, generic::exp_digamma_minus,
                       generic::axpy,      generic::digamma_one};
#ifdef PROPRIO_TOPICS_X86
const Kernels kAvx2{"avx2",           8, avx2::estep_doc, avx2::exp_digamma_minus, avx2::axpy,
                    avx2::digamma_one};
const Kernels kAvx512{
    "avx512", 16, avx512::estep_doc, avx512::exp_digamma_minus, avx512::axpy, avx512::digamma_one};

bool has_avx2() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
bool has_avx512() {
  return has_avx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512dq");
}
#endif

}  // namespace

std::vector<std::string> supported_kernels() {
  std::vector<std::string> names{"generic"};
#ifdef PROPRIO_TOPICS_X86
  if (has_avx2()) names.emplace_back("avx2");
  if (has_avx512()) names.emplace_back("avx512");
#endif
  return names;
}

const Kernels& kernels_named(std::string_view name) {
  if (name == "generic") return kGeneric;
#ifdef PROPRIO_TOPICS_X86
  if (name == "avx2" && has_avx2()) return kAvx2;
  if (name == "avx512" && has_avx512()) return kAvx512;
#endif
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
#ifdef PROPRIO_TOPICS_X86
    if (has_avx512()) return kAvx512;
    if (has_avx2()) return kAvx2;
#endif
    return kGeneric;
  }();
  return chosen;
}

}  // namespace proprio::topics::detail
