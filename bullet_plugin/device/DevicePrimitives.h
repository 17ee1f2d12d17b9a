// Sort by key and exclusive scan on the device, for the global split.
//
// Why two backends. On CPU devices, hand-written kernels (kernels/primitives.cl): a chunked
// counting sort (one O(n + buckets) pass, for keys below a known range), a chunked LSD radix
// sort built from the same passes, and a chunked scan. There Boost.Compute's sort is a merge
// sort whose last passes run on few work-items, many times slower, and Boost.Compute compiles
// its programs at first use, once per OpenCL context, which makes start-up slower too. On other
// devices (GPUs) neither is sure to win: Boost.Compute's radix sort and work-efficient scan use
// lanes that a few long serial chunks waste, but take many more launches. There both are timed on the split's work when the first solver starts,
// and the faster is kept (fasterBackend). The CPU figures, and the command that gives them, are
// in demos/bench/README.md ("Sort and scan: our kernels against Boost.Compute").
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
    // Auto: Chunked on CPU devices, fasterBackend(rt) on others.
    enum class Backend { Auto, Chunked, BoostCompute };

    // The backend that does a split's sort and scans faster on rt's device, timed by the host's
    // clock from enqueue to finish (launches and waits are part of a step's cost), at two sizes.
    // Measured once per device in a process (about a second, most of it building both), then
    // remembered. Throws btOpenCLSolverError.
    struct BackendTiming {
        Backend faster = Backend::Chunked;
        double msChunked = 0, msBoostCompute = 0;  // the split's work at both sizes, best runs
    };
    static BackendTiming timeBackends(const OclRuntime& rt);
    static Backend fasterBackend(const OclRuntime& rt) { return timeBackends(rt).faster; }

    // Builds every kernel here and, unless `warmUpNow` is false, warms them up (warmUp()).
    // `rt` must outlive this object. Throws btOpenCLSolverError.
    explicit DevicePrimitives(const OclRuntime& rt, Backend backend = Backend::Auto, bool warmUpNow = true);
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

    // Runs every path of the sort and scan once (Boost.Compute compiles its programs at their
    // first use), so that no step pays for their compiles. Throws btOpenCLSolverError.
    void warmUp();

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
