#pragma once
// AGGKIT_SIMD_CLONES before a function with vectorised loops compiles it three times, for x86-64-v4
// (AVX-512), x86-64-v3 (AVX2 + FMA) and the baseline (SSE2), and picks one at load time for the CPU it runs
// on (GCC's target_clones; a build for the baseline still runs everywhere). One machine always runs the
// same version, so results stay bit-identical from run to run and for any thread count; two machines with
// different vector units may differ in the last bits (lane count of the reductions, fused multiply-adds).
// Elsewhere (other compilers or architectures) it expands to nothing, and a build can switch it off with
// -DAGGKIT_SIMD_CLONES= (then the flags alone choose the vector unit).
#if defined(AGGKIT_SIMD_CLONES)
#elif defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define AGGKIT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define AGGKIT_SIMD_CLONES
#endif
