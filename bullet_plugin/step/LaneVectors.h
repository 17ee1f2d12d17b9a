// Eight float lanes (AVX2) as GCC's vector types, for the host's lanes (HostLaneSolve.cpp,
// LaneRowSetup.cpp). Every function here and in its users is built for AVX2 whatever the build's
// target, and called only where the CPU has it (lanesAvailable): each has the target attribute
// and internal linkage, so no other code is built for AVX2. The solve's and the setup's loops are
// built a second time for AVX-512VL, inlining the same functions, and run where the CPU has it.
#pragma once

#include <atomic>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BTOCL_LANES_TARGET __attribute__((target("avx2")))
// The same eight lanes with AVX-512VL's 32 vector registers (AVX2 has 16): the solve's two sides
// of a slot, about 30 vectors, stay in registers (lanesUseWideRegisters).
#define BTOCL_LANES_WIDE_REGISTERS_TARGET __attribute__((target("avx2,avx512f,avx512vl")))
#define BTOCL_HAS_HOST_LANES 1
#else
#define BTOCL_LANES_TARGET
#define BTOCL_LANES_WIDE_REGISTERS_TARGET
#define BTOCL_HAS_HOST_LANES 0
#endif
// Inlined into their callers, where the lanes stay in registers.
#define BTOCL_LANES_INLINE BTOCL_LANES_TARGET inline __attribute__((always_inline))

namespace btocl {

// Whether this CPU runs the lanes' code (x86-64 with AVX2).
inline bool lanesAvailable() {
#if BTOCL_HAS_HOST_LANES
    return __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}

// Whether the lanes' solve and setup run their AVX-512VL builds (BTOCL_LANES_WIDE_REGISTERS_TARGET):
// where the CPU has it, unless switched off (the tests compare the two builds' bits). Atomic: solvers
// in other threads read it.
inline std::atomic<bool>& lanesUseWideRegisters() {
#if BTOCL_HAS_HOST_LANES
    static std::atomic<bool> use{__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")};
#else
    static std::atomic<bool> use{false};
#endif
    return use;
}

namespace {

constexpr int W = 8;
typedef float Lanes __attribute__((vector_size(4 * W)));
typedef int LaneMask __attribute__((vector_size(4 * W)));

BTOCL_LANES_INLINE Lanes load(const float* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
BTOCL_LANES_INLINE LaneMask loadInts(const int* p) {
    LaneMask v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
BTOCL_LANES_INLINE void store(Lanes v, float* p) { std::memcpy(p, &v, sizeof v); }
// OpenCL's select(a, b, m): b where m is set, else a.
BTOCL_LANES_INLINE Lanes select(Lanes a, Lanes b, LaneMask m) { return m ? b : a; }
BTOCL_LANES_INLINE Lanes splat(float x) { return Lanes{} + x; }
// Whether any lane of m is set.
BTOCL_LANES_INLINE bool anyLane(LaneMask m) { return !_mm256_testz_si256((__m256i)m, (__m256i)m); }
// An 8x8 transpose: out[f] holds float f of every in[i] (lane i of in[f] is float f of out[i]).
// Shuffles only, so every float keeps its bits; its own inverse.
BTOCL_LANES_INLINE void transpose8(const Lanes* in, Lanes* out) {
    __m256 r[8];
    for (int i = 0; i < 8; ++i) r[i] = (__m256)in[i];
    __m256 t[8], u[8];
    for (int i = 0; i < 8; i += 2) {
        t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]);
        t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
    }
    for (int i = 0; i < 8; i += 4) {
        u[i] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44);
        u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xee);
        u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44);
        u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xee);
    }
    for (int f = 0; f < 4; ++f) {
        out[f] = (Lanes)_mm256_permute2f128_ps(u[f], u[f + 4], 0x20);
        out[f + 4] = (Lanes)_mm256_permute2f128_ps(u[f], u[f + 4], 0x31);
    }
}

// Eight records of eight floats, the i-th at p[i], as eight vectors: out[f] holds float f of each
// (lane i of record i).
BTOCL_LANES_INLINE void transpose8(const float* const* p, Lanes* out) {
    Lanes r[8];
    for (int i = 0; i < 8; ++i) r[i] = load(p[i]);
    transpose8(r, out);
}

}  // namespace
}  // namespace btocl
