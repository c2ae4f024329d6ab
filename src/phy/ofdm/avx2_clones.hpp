#pragma once
// RFSITL_AVX2_CLONES: a function compiled twice, for AVX2 and for plain
// x86-64, one of which the CPU picks when the program loads (GCC's
// target_clones, an ifunc). No FMA in either: both round alike, so a result
// does not depend on the machine.
//
// Not under ThreadSanitizer: the ifunc's resolver runs while the dynamic
// loader relocates the program, before TSan's runtime is set up, and the
// instrumented resolver crashes every TSan binary at load.
#if defined(__SANITIZE_THREAD__)
#define RFSITL_AVX2_CLONES
#else
#define RFSITL_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif
