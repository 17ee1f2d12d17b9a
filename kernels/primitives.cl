// Device primitives for the global split: a counting sort of (uint key, int value) pairs and an
// exclusive scan, written for CPU devices (PoCL). Each work-item owns one contiguous chunk of the
// input and walks it in order; there are no atomics. Walking in order is what makes the sort
// stable, and having no atomics is what makes every run bitwise the same.
// Launch each kernel with one work-item per chunk (work-groups of 1): global size = numChunks.
// A chunk keeps its bucket counters in local memory: counters of neighbouring chunks in one
// global array would share cache lines between cores on every increment.
// Sums wrap as uint, which gives the same bits as two's-complement int arithmetic.

// Histogram of one chunk. bucket(key) = (key >> shift) & mask. counts is bucket-major,
// counts[b * numChunks + c] = how many keys of chunk c fall in bucket b, so one exclusive scan
// over counts gives every (bucket, chunk) its first output position. A bucket past numBuckets
// is clamped to the extra bucket numBuckets (counts has numBuckets + 1 rows), so a bad key can
// never write outside the buffers; a key above keyMax sets *badKeys.
__kernel void countChunkBuckets(__global const uint* keys, uint n, uint chunkLen, uint shift,
                                uint mask, uint numBuckets, uint keyMax, __global uint* counts,
                                __global uint* badKeys, __local uint* hist) {
    const uint c = get_global_id(0);
    const uint numChunks = get_global_size(0);
    for (uint b = 0; b <= numBuckets; ++b) hist[b] = 0;
    const uint begin = min(n, c * chunkLen);
    const uint end = min(n, begin + chunkLen);
    uint bad = 0;
    for (uint i = begin; i < end; ++i) {
        const uint key = keys[i];
        bad |= key > keyMax;
        hist[min((key >> shift) & mask, numBuckets)] += 1;
    }
    for (uint b = 0; b <= numBuckets; ++b) counts[b * numChunks + c] = hist[b];
    if (bad) *badKeys = 1;  // every writer stores the same value
}

// Moves each pair of chunk c to its place. offsets = the exclusive scan of countChunkBuckets'
// counts: this chunk's column of it is where each of its buckets starts.
__kernel void scatterChunkBuckets(__global const uint* keysIn, __global const int* valuesIn, uint n,
                                  uint chunkLen, uint shift, uint mask, uint numBuckets,
                                  __global const uint* offsets, __global uint* keysOut,
                                  __global int* valuesOut, __local uint* next) {
    const uint c = get_global_id(0);
    const uint numChunks = get_global_size(0);
    for (uint b = 0; b <= numBuckets; ++b) next[b] = offsets[b * numChunks + c];
    const uint begin = min(n, c * chunkLen);
    const uint end = min(n, begin + chunkLen);
    for (uint i = begin; i < end; ++i) {
        const uint key = keysIn[i];
        const uint pos = next[min((key >> shift) & mask, numBuckets)]++;
        keysOut[pos] = key;
        valuesOut[pos] = valuesIn[i];
    }
}

// Scan, step 1 of 2: the sum of each chunk.
__kernel void sumChunks(__global const uint* in, uint n, uint chunkLen, __global uint* chunkSums) {
    const uint c = get_global_id(0);
    const uint begin = min(n, c * chunkLen);
    const uint end = min(n, begin + chunkLen);
    uint sum = 0;
    for (uint i = begin; i < end; ++i) sum += in[i];
    chunkSums[c] = sum;
}

// Scan, step 2 of 2: out[i] = sum of in[0..i-1]. Each element is read before it is written, by
// the one work-item that owns it, so in and out may be the same buffer. chunkSums is unused
// (may be any buffer) when there is one chunk.
__kernel void scanChunks(__global const uint* in, __global uint* out, uint n, uint chunkLen,
                         __global const uint* chunkSums) {
    const uint c = get_global_id(0);
    const uint begin = min(n, c * chunkLen);
    const uint end = min(n, begin + chunkLen);
    uint run = 0;
    for (uint j = 0; j < c; ++j) run += chunkSums[j];
    for (uint i = begin; i < end; ++i) {
        const uint v = in[i];
        out[i] = run;
        run += v;
    }
}
