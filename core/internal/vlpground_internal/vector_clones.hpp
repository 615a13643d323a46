// Internal to the project (never installed): include with
// target_include_directories(<target> PRIVATE ${PROJECT_SOURCE_DIR}/core/internal).
//
// Builds a hot function twice, for the x86-64 baseline (SSE2) and for AVX2 + FMA
// (x86-64-v3), picking one at load time (GCC function multi-versioning through ifunc).
// The binary stays portable to any x86-64; machines from 2013 on get the wide version.
// `flatten` inlines the callees so that they too are built for each target.
#pragma once

// GCC only: clang 14 does not accept arch= in target_clones. Off under ASan, so that the
// sanitizer build also tests the baseline version.
#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(VLPGROUND_NO_VECTOR_CLONES) && !defined(__SANITIZE_ADDRESS__)
#define VLPGROUND_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default"), flatten))
#else
#define VLPGROUND_VECTOR_CLONES
#endif
