// Priority of a constraint in the locking rounds of the local batching, shared by the device
// (kernels/batch.cl) and its host twin. Lower wins. A hash of the constraint index comes first: with
// plain index order, a lattice of contacts forms long chains of ever-smaller indices and the rounds
// resolve only a few links of each chain, leaving batches half full; a hashed order breaks the chains
// (as in Luby's parallel independent sets) at the same determinism. The window position comes last,
// so priorities are unique and the smallest pending one always wins.
#ifndef BTOCL_BATCH_PRIORITY_H
#define BTOCL_BATCH_PRIORITY_H

#include "btocl_shared.h"

// windowBits: bits of a window position (window <= 2^windowBits); the result is below 2^30.
BTOCL_INLINE int btoclBatchPriority(int constraintIndex, int windowPos, int windowBits) {
    unsigned int h = (unsigned int)constraintIndex;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return (int)(((h >> (windowBits + 2)) << windowBits) | (unsigned int)windowPos);
}

// Bits of a window position: the smallest b with windowSize <= 2^b.
BTOCL_INLINE int btoclBatchWindowBits(int windowSize) {
    int bits = 0;
    while ((1 << bits) < windowSize) ++bits;
    return bits;
}

#endif
