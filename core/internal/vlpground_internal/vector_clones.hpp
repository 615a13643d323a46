// Internal to the project (never installed): include with
// target_include_directories(<target> PRIVATE ${PROJECT_SOURCE_DIR}/core/internal).
//
// Builds a hot function three times, for the x86-64 baseline (SSE2), for AVX2 + FMA
// (x86-64-v3) and for AVX-512 (x86-64-v4), picking one at load time (GCC function
// multi-versioning through ifunc). The binary stays portable to any x86-64; machines from
// 2013 on get the wide version. The AVX-512 version mostly gains the 32 vector registers:
// the inlier scoring keeps more of its plane block, counts and thresholds in registers
// where v3 spills them (docs/detector.md, "Speed"). v4 and v3 contract the same products
// into FMAs: their labels are the same on all 3420 evaluation captures and the real ones.
// `flatten` inlines the callees so that they too are built for each target.
#pragma once

// GCC only: clang 14 does not accept arch= in target_clones. Off under ASan, so that the
// sanitizer build also tests the baseline version.
#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(VLPGROUND_NO_VECTOR_CLONES) && !defined(__SANITIZE_ADDRESS__)
#define VLPGROUND_VECTOR_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"), flatten))
#endif

#include <cstddef>

namespace vlpground::detail {
/// Bytes per vector of the widest build (AVX-512) and of the AVX2 one: kernels size their
/// blocks and paddings from these.
inline constexpr std::size_t kWidestVectorBytes = 64, kAvx2VectorBytes = 32;

/// Whether the AVX-512 (x86-64-v4) builds of VLPGROUND_VECTOR_CLONES functions are the ones
/// that run here: the same test as the load-time pick.
inline bool avx512_clones_run() {
#ifdef VLPGROUND_VECTOR_CLONES
  static const bool v4 = __builtin_cpu_supports("x86-64-v4");
  return v4;
#else
  return false;
#endif
}
}  // namespace vlpground::detail

#ifndef VLPGROUND_VECTOR_CLONES
#define VLPGROUND_VECTOR_CLONES
#endif
