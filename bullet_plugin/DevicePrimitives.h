// Sort by key and exclusive scan on the device, for the global split.
//
// Why hand-written kernels (kernels/primitives.cl) and not Boost.Compute, on CPU devices:
// `build-P/demos/bench_primitives 15 4096` (PoCL, 2 cores, with other builds running, so +-30%;
// ms, median of 15 after warm-up), sort of n (key < 4096, int) pairs:
//        n   chunked counting sort   Boost stable_sort_by_key   Boost radix_sort_by_key
//    10000          0.09                    0.76                       1.06
//    60000          0.15                    4.6                        9.6
//   300000          0.70                   26.8                       58.5
// On a CPU device Boost.Compute's sort is a merge sort whose last passes run on few work-items;
// the counting sort is one O(n + buckets) pass. With the same kernels, a 12-bit radix (two
// passes) is slower than the one counting pass at every size (300K: 1.18 ms), and a full 32-bit
// radix sorts random keys 10x faster than Boost (300K: 3.5 vs 31 ms). The exclusive scans are
// equal within noise (300K: 0.13 vs 0.18 ms). Start-up too: Boost.Compute compiles its programs
// at first use, 3.9 s cold / 0.36 s warm PoCL cache, once per OpenCL context (kept in memory:
// a second object on the same context pays 1 ms); the chunked program costs 0.9 s cold / 0.05 s
// warm (`demos/startup --cold-warm --boost`). Boost.Compute stays the backend for other devices
// (GPUs: a few long serial chunks would waste them); there is no GPU here to measure it on.
//
// Host round trips: none, except the 4-byte read of checkKeys() (see sortByKeySmallRange).
// Scratch memory (n keys, n values, the bucket counts) is kept and grown, never shrunk.
#pragma once

#include "DeviceBuffer.h"
#include "OclRuntime.h"

#include <cstddef>
#include <memory>

namespace btocl {

class DevicePrimitives {
public:
    // Auto: Chunked on CPU devices, BoostCompute on others (Boost.Compute's GPU paths are a
    // radix sort and a work-efficient scan; the chunked kernels give a GPU only a few lanes).
    enum class Backend { Auto, Chunked, BoostCompute };

    // Builds (or, for Boost.Compute, compiles and warms up) every kernel here, so the first
    // step pays nothing more. `rt` must outlive this object. Throws btOpenCLSolverError.
    explicit DevicePrimitives(const OclRuntime& rt, Backend backend = Backend::Auto);
    ~DevicePrimitives();
    DevicePrimitives(const DevicePrimitives&) = delete;
    DevicePrimitives& operator=(const DevicePrimitives&) = delete;

    // Stable sort of n (uint key, int value) pairs in place, on the device, by the whole key.
    // Enqueued on rt.queue(); nothing returns to the host.
    void sortByKey(const cl::Buffer& keys, const cl::Buffer& values, size_t n);

    // LSD radix sort by the low keyBits bits (1..32) of the key, in passes of at most 8 bits;
    // a key >= 2^keyBits is reported as in sortByKeySmallRange. sortByKey = keyBits 32.
    // (Chunked backend; BoostCompute sorts by the whole key.)
    void sortByKeyBits(const cl::Buffer& keys, const cl::Buffer& values, size_t n, unsigned keyBits,
                       bool check = true);

    // The same for keys < maxKeyExclusive (e.g. cell indices): a counting sort, one pass.
    // A key >= maxKeyExclusive is never written out of bounds; the output is then unsorted and
    // the next checkKeys() throws. With check = true this call runs checkKeys() itself: a 4-byte
    // blocking read, the one host round trip here (pass false and call checkKeys() once per
    // step to avoid it). maxKeyExclusive must be >= 1 and at most maxSmallKeyRange().
    void sortByKeySmallRange(const cl::Buffer& keys, const cl::Buffer& values, size_t n,
                             unsigned maxKeyExclusive, bool check = true);
    static unsigned maxSmallKeyRange() { return 1u << 20; }

    // Waits for the queue; throws btOpenCLSolverError if a key past its range reached
    // sortByKeySmallRange since the last check, and clears the flag.
    void checkKeys();

    // out[i] = in[0] + ... + in[i-1] (int, wrapping), out[0] = 0, on the device. in and out
    // may be the same buffer (in-place scan).
    void exclusiveScan(const cl::Buffer& in, const cl::Buffer& out, size_t n);

    Backend backend() const { return m_backend; }
    const char* backendName() const;

private:
    struct Boost;
    size_t chunksFor(size_t n, size_t minChunkLen) const;
    void countingPass(const cl::Buffer& keysIn, const cl::Buffer& valuesIn, const cl::Buffer& keysOut,
                      const cl::Buffer& valuesOut, size_t n, unsigned shift, unsigned mask,
                      unsigned numBuckets, unsigned keyMax);
    void radixSort(const cl::Buffer& keys, const cl::Buffer& values, size_t n, unsigned keyBits, unsigned keyMax);
    void scanChunked(const cl::Buffer& in, const cl::Buffer& out, size_t n);
    void launch(cl::Kernel& kernel, size_t numChunks, const char* what);

    const OclRuntime& m_rt;
    Backend m_backend;
    size_t m_maxChunks = 1;
    std::unique_ptr<Boost> m_boost;
    cl::Kernel m_count, m_scatter, m_sumChunks, m_scanChunks;
    DeviceBuffer<cl_uint> m_tmpKeys, m_tmpValues, m_counts, m_chunkSums, m_badKeys;
};

}  // namespace btocl
