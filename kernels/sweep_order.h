// The order in which an iteration walks a group: a pseudo-random permutation, fresh each
// iteration and the same from run to run (seeded by the step and the iteration), shared by the
// device (kernels/solve.cl) and the serial host reference. Like SI's SOLVER_RANDMIZE_ORDER, a
// changing order keeps Gauss-Seidel's bias from pushing resting stacks the same way step after
// step: they drift and jitter less than with one fixed order (measured: README).
#ifndef BTOCL_SWEEP_ORDER_H
#define BTOCL_SWEEP_ORDER_H

#include "btocl_shared.h"

// A bijection of [0, n): a keyed mix on the smallest power of two >= n (each step invertible:
// xor, odd multiply, xor-shift), walked until it lands below n (fewer than two steps on average).
typedef struct {
    unsigned int n, mask, seed;
    int shift;
} btoclPermutation;

BTOCL_INLINE unsigned int btoclHash(unsigned int x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

BTOCL_INLINE btoclPermutation btoclMakePermutation(int n, unsigned int seed) {
    btoclPermutation p;
    int bits = 1;
    while ((1 << bits) < n) ++bits;
    p.n = (unsigned int)n;
    p.mask = (1u << bits) - 1u;
    p.shift = (bits + 1) / 2;
    p.seed = seed;
    return p;
}

BTOCL_INLINE int btoclPermute(btoclPermutation p, int j) {
    if (p.n <= 1u) return j;
    unsigned int x = (unsigned int)j;
    do {
        x = (x ^ p.seed) & p.mask;
        x = (x * 0x9E3779B1u) & p.mask;
        x ^= x >> p.shift;
        x = (x * 0x85EBCA6Bu) & p.mask;
        x ^= x >> p.shift;
    } while (x >= p.n);
    return (int)x;
}

// A run of n constraints walked by one work-item goes chunk by chunk in a permuted order, each
// chunk front to back. A whole step solved in one launch is small enough to stay in cache: one
// constraint a chunk. The groups of a large step are streamed from memory at every pass: at most
// this many chunks, so that they still stream (a fully permuted walk of a 12K-box block's groups
// cost the solve 1.5x the CPU time), while the small groups of a resting stack are still permuted
// one constraint at a time.
#define BTOCL_SWEEP_MAX_CHUNKS 32
BTOCL_INLINE int btoclSweepChunkLength(int n, int wholeStep) {
    return (wholeStep || n <= BTOCL_SWEEP_MAX_CHUNKS) ? 1 : (n + BTOCL_SWEEP_MAX_CHUNKS - 1) / BTOCL_SWEEP_MAX_CHUNKS;
}

// The seed of one iteration of one pass kind (0: the velocity iterations, 1: the split-impulse
// ones) of a step; 0 means "in order" (the seed is never 0 otherwise).
BTOCL_INLINE unsigned int btoclIterationSeed(unsigned int stepSeed, int kind, int iteration) {
    return btoclHash(stepSeed ^ btoclHash((unsigned int)(iteration * 2 + kind) + 0x9e3779b9u)) | 1u;
}

#endif
