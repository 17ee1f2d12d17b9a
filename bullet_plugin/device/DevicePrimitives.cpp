#include "DevicePrimitives.h"

#include "btOpenCLSolverError.h"
#include "split_grid.h"

#include <boost/compute/algorithm/exclusive_scan.hpp>
#include <boost/compute/algorithm/stable_sort_by_key.hpp>
#include <boost/compute/command_queue.hpp>
#include <boost/compute/container/vector.hpp>
#include <boost/compute/context.hpp>
#include <boost/compute/iterator/buffer_iterator.hpp>
#include <boost/compute/utility/program_cache.hpp>

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace btocl {
namespace bc = boost::compute;

namespace {

// Boost.Compute keeps its programs in a process-wide cache (program_cache::get_global_cache, and
// the tuning parameters' parameter_cache) that has no lock unless BOOST_COMPUTE_THREAD_SAFE is
// defined, and then one cache per thread, which would build a solver's programs again in every
// thread that steps it. So every call into Boost.Compute here holds this one lock instead. The
// cache also keeps a context's programs, and through them the context, after its last user is
// gone: the last Boost of a context clears them (`users`).
struct BoostComputeShared {
    std::mutex mutex;
    std::map<cl_context, int> users;
};
BoostComputeShared& boostComputeShared() {
    // Never destroyed: a DevicePrimitives that outlives main (a static solver) still takes the lock.
    static BoostComputeShared* shared = new BoostComputeShared;
    return *shared;
}

}  // namespace

// The runtime's context and queue seen through Boost.Compute (both retained: Boost.Compute's
// wrappers release what they hold). Hold lock() around every Boost.Compute call.
struct DevicePrimitives::Boost {
    explicit Boost(const OclRuntime& rt) : context(rt.context()(), true), queue(rt.queue()(), true) {
        const std::lock_guard<std::mutex> guard(lock());
        programs = bc::program_cache::get_global_cache(context);
        ++boostComputeShared().users[context.get()];
    }
    ~Boost() {
        const std::lock_guard<std::mutex> guard(lock());
        auto& users = boostComputeShared().users;
        const auto it = users.find(context.get());
        if (--it->second > 0) return;
        users.erase(it);
        programs->clear();
    }
    static std::mutex& lock() { return boostComputeShared().mutex; }
    bc::context context;
    bc::command_queue queue;
    // The cache's programs of this context, held here: cleared through this pointer, the cache is
    // reached even after Boost.Compute's own static, which holds it too, is gone at exit. (With
    // more than eight contexts in use at once, Boost.Compute may drop this cache from its own and
    // start another for the context, which this pointer does not reach: that one goes when it is
    // dropped in turn.)
    boost::shared_ptr<bc::program_cache> programs;
};

namespace {

constexpr size_t kScanMinChunk = 16384;     // below this a chunk costs more to launch than to walk
constexpr size_t kSortMinChunk = 4096;
constexpr unsigned kRadixBits = 8;          // 256 buckets per radix pass

void requireBytes(const cl::Buffer& buffer, size_t n, const char* what) {
    if (n > size_t(std::numeric_limits<cl_int>::max()))
        throw btOpenCLSolverError(std::string("DevicePrimitives::") + what + ": " + std::to_string(n) +
                                  " elements is more than 2^31 - 1");
    if (n == 0) return;
    size_t bytes = 0;
    if (!buffer() || buffer.getInfo(CL_MEM_SIZE, &bytes) != CL_SUCCESS || bytes < n * 4)
        throw btOpenCLSolverError(std::string("DevicePrimitives::") + what + ": a buffer of " +
                                  std::to_string(bytes) + " bytes cannot hold " + std::to_string(n) +
                                  " elements of 4 bytes");
}

size_t ceilDiv(size_t a, size_t b) { return (a + b - 1) / b; }

// What the split and arrange steps ask of the primitives for n constraints: a sort by cell key
// (keys below BTOCL_SPLIT_NUM_KEYS, scattered), the scan of the key bins and the two scans of
// row counts. Milliseconds from the first enqueue to the finished queue, the best of a few runs.
double msOfSplitWork(DevicePrimitives& prims, const OclRuntime& rt, size_t n) {
    std::vector<cl_uint> keys(n), values(n);
    for (size_t i = 0; i < n; ++i) {
        keys[i] = cl_uint((i * 2654435761u) >> 7) % BTOCL_SPLIT_NUM_KEYS;
        values[i] = cl_uint(i);
    }
    DeviceBuffer<cl_uint> k, v, bins, rows;
    bins.fill(rt, 1u, BTOCL_SPLIT_NUM_KEYS);
    rows.fill(rt, 3u, n);
    double best = std::numeric_limits<double>::infinity();
    for (int run = 0; run < 4; ++run) {
        k.write(rt, keys);  // the sort works in place: each run starts from the same keys
        v.write(rt, values);
        const auto start = std::chrono::steady_clock::now();
        prims.sortByKeySmallRange(k.buffer(), v.buffer(), n, BTOCL_SPLIT_NUM_KEYS, false);
        prims.exclusiveScan(bins.buffer(), bins.buffer(), BTOCL_SPLIT_NUM_KEYS);
        prims.exclusiveScan(rows.buffer(), rows.buffer(), n);
        prims.exclusiveScan(rows.buffer(), rows.buffer(), n);
        rt.finish("timing the sort and scan");
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
}

}  // namespace

DevicePrimitives::BackendTiming DevicePrimitives::timeBackends(const OclRuntime& rt) {
    static std::mutex mutex;
    static std::map<cl_device_id, BackendTiming> measured;
    const std::lock_guard<std::mutex> lock(mutex);
    const auto known = measured.find(rt.device()());
    if (known != measured.end()) return known->second;
    // A small step's work (launches weigh most) and a large one's (a 12K-box block has about
    // 90K constraints). The backends' results are the same (stable sorts, exact integer scans), so
    // the choice changes no step's outcome, only its time.
    BackendTiming t;
    for (const Backend backend : {Backend::Chunked, Backend::BoostCompute}) {
        DevicePrimitives prims(rt, backend);
        double& ms = backend == Backend::Chunked ? t.msChunked : t.msBoostCompute;
        for (const size_t n : {size_t(4096), size_t(98304)}) ms += msOfSplitWork(prims, rt, n);
    }
    t.faster = t.msChunked <= t.msBoostCompute ? Backend::Chunked : Backend::BoostCompute;
    measured.emplace(rt.device()(), t);
    return t;
}

DevicePrimitives::DevicePrimitives(const OclRuntime& rt, Backend backend, bool warmUpNow)
    : m_rt(rt), m_backend(backend) {
    if (m_backend == Backend::Auto && rt.isCpu()) m_backend = Backend::Chunked;
    if (m_backend == Backend::Auto) {
        // Made first, so that the timing's own Boost.Compute programs stay in the cache for it.
        m_boost = std::make_unique<Boost>(rt);
        m_backend = fasterBackend(rt);
        if (m_backend == Backend::Chunked) m_boost.reset();
    }
    m_maxChunks = std::min<size_t>(4 * rt.computeUnits(), 256);  // a few chunks per core balance the load

    if (m_backend == Backend::Chunked) {
        const cl::Program& program = rt.stepProgram();  // primitives.cl among the step's kernels
        m_count = rt.makeKernel(program, "countChunkBuckets");
        m_scatter = rt.makeKernel(program, "scatterChunkBuckets");
        m_sumChunks = rt.makeKernel(program, "sumChunks");
        m_scanChunks = rt.makeKernel(program, "scanChunks");
        m_chunkSums.reserve(rt, m_maxChunks);
        m_badKeys.fill(rt, 0u, 1);
    } else if (!m_boost) {
        m_boost = std::make_unique<Boost>(rt);
    }
    if (warmUpNow) warmUp();
}

void DevicePrimitives::warmUp() {
    const OclRuntime& rt = m_rt;
    // Warm-up: PoCL compiles a kernel for its launch shape at the first launch, and
    // Boost.Compute compiles its programs at first use (cached per context). Run every path
    // once now so that no solver step pays for it. 70000 > Boost's serial-scan threshold,
    // 600 > its insertion-sort-only size.
    const size_t warmN = m_backend == Backend::Chunked ? 2 * kScanMinChunk : 70000;
    std::vector<cl_uint> keys(warmN);
    for (size_t i = 0; i < warmN; ++i) keys[i] = cl_uint((i * 7919) % 1000);
    DeviceBuffer<cl_uint> k, v;
    k.write(rt, keys);
    v.write(rt, keys);
    sortByKeySmallRange(k.buffer(), v.buffer(), 600, 1000, false);
    sortByKey(k.buffer(), v.buffer(), 600);
    exclusiveScan(v.buffer(), v.buffer(), warmN);
    exclusiveScan(v.buffer(), v.buffer(), 100);
    checkKeys();
}

DevicePrimitives::~DevicePrimitives() = default;

const char* DevicePrimitives::backendName() const {
    return m_backend == Backend::Chunked ? "chunked" : "boost.compute";
}

size_t DevicePrimitives::chunksFor(size_t n, size_t minChunkLen) const {
    return std::max<size_t>(1, std::min(m_maxChunks, n / minChunkLen));
}

void DevicePrimitives::launch(cl::Kernel& kernel, size_t numChunks, const char* what) {
    m_rt.launch(kernel, numChunks, 1, what);  // one work-item per chunk
}

void DevicePrimitives::sortByKey(const cl::Buffer& keys, const cl::Buffer& values, size_t n) {
    sortByKeyBits(keys, values, n, 32, false);
}

void DevicePrimitives::sortByKeyBits(const cl::Buffer& keys, const cl::Buffer& values, size_t n,
                                     unsigned keyBits, bool check) {
    requireBytes(keys, n, "sortByKey (keys)");
    requireBytes(values, n, "sortByKey (values)");
    if (keyBits < 1 || keyBits > 32)
        throw btOpenCLSolverError("DevicePrimitives::sortByKeyBits: keyBits must be 1..32, not " +
                                  std::to_string(keyBits));
    if (m_boost) {
        if (n < 2) return;
        bc::buffer k(keys(), true), v(values(), true);
        const std::lock_guard<std::mutex> guard(Boost::lock());
        bc::stable_sort_by_key(bc::make_buffer_iterator<bc::uint_>(k, 0), bc::make_buffer_iterator<bc::uint_>(k, n),
                               bc::make_buffer_iterator<bc::int_>(v, 0), m_boost->queue);
        return;
    }
    if (n >= 1) radixSort(keys, values, n, keyBits, keyBits == 32 ? 0xffffffffu : (1u << keyBits) - 1);
    if (check) checkKeys();
}

void DevicePrimitives::radixSort(const cl::Buffer& keys, const cl::Buffer& values, size_t n, unsigned keyBits,
                                 unsigned keyMax) {
    m_tmpKeys.reserve(m_rt, n);
    m_tmpValues.reserve(m_rt, n);
    const unsigned passes = (keyBits + kRadixBits - 1) / kRadixBits;
    const unsigned digitBits = (keyBits + passes - 1) / passes;  // 12 bits: 2 passes of 6
    for (unsigned p = 0; p < passes; ++p) {
        const bool fromOriginal = (p % 2) == 0;
        countingPass(fromOriginal ? keys : m_tmpKeys.buffer(), fromOriginal ? values : m_tmpValues.buffer(),
                     fromOriginal ? m_tmpKeys.buffer() : keys, fromOriginal ? m_tmpValues.buffer() : values, n,
                     p * digitBits, (1u << digitBits) - 1, 1u << digitBits, p == 0 ? keyMax : 0xffffffffu);
    }
    if (passes % 2) {  // the result is in the temporaries
        checkCl(m_rt.queue().enqueueCopyBuffer(m_tmpKeys.buffer(), keys, 0, 0, n * 4), "sortByKey: copy back");
        checkCl(m_rt.queue().enqueueCopyBuffer(m_tmpValues.buffer(), values, 0, 0, n * 4), "sortByKey: copy back");
    }
}

void DevicePrimitives::sortByKeySmallRange(const cl::Buffer& keys, const cl::Buffer& values, size_t n,
                                           unsigned maxKeyExclusive, bool check) {
    requireBytes(keys, n, "sortByKeySmallRange (keys)");
    requireBytes(values, n, "sortByKeySmallRange (values)");
    if (maxKeyExclusive < 1 || maxKeyExclusive > maxSmallKeyRange())
        throw btOpenCLSolverError("DevicePrimitives::sortByKeySmallRange: maxKeyExclusive must be 1.." +
                                  std::to_string(maxSmallKeyRange()) + ", not " + std::to_string(maxKeyExclusive));
    if (n < 2 && !check) return;
    if (m_boost) {
        sortByKey(keys, values, n);  // a general sort: any key lands in its place
        return;
    }
    if ((size_t(maxKeyExclusive) + 1) * 4 > m_rt.localMemSize()) {
        // The counters do not fit in local memory: radix passes over the bits the keys may use.
        unsigned bits = 1;
        while ((1ull << bits) < maxKeyExclusive) ++bits;
        if (n >= 1) radixSort(keys, values, n, bits, maxKeyExclusive - 1);
        if (check) checkKeys();
        return;
    }
    if (n >= 1) {
        m_tmpKeys.reserve(m_rt, n);
        m_tmpValues.reserve(m_rt, n);
        countingPass(keys, values, m_tmpKeys.buffer(), m_tmpValues.buffer(), n, 0, 0xffffffffu, maxKeyExclusive,
                     maxKeyExclusive - 1);
        checkCl(m_rt.queue().enqueueCopyBuffer(m_tmpKeys.buffer(), keys, 0, 0, n * 4), "sortByKeySmallRange: copy back");
        checkCl(m_rt.queue().enqueueCopyBuffer(m_tmpValues.buffer(), values, 0, 0, n * 4),
                "sortByKeySmallRange: copy back");
    }
    if (check) checkKeys();
}

void DevicePrimitives::countingPass(const cl::Buffer& keysIn, const cl::Buffer& valuesIn, const cl::Buffer& keysOut,
                                    const cl::Buffer& valuesOut, size_t n, unsigned shift, unsigned mask,
                                    unsigned numBuckets, unsigned keyMax) {
    // Chunks also cost a histogram row each: keep rows x chunks under about n / 4.
    const size_t rows = size_t(numBuckets) + 1;
    const size_t chunks = std::max<size_t>(1, std::min(chunksFor(n, kSortMinChunk), n / (4 * rows)));
    const cl_uint chunkLen = cl_uint(ceilDiv(n, chunks));
    m_counts.reserve(m_rt, rows * chunks);

    setArgs(m_count, keysIn, cl_uint(n), chunkLen, cl_uint(shift), cl_uint(mask), cl_uint(numBuckets), cl_uint(keyMax),
            m_counts.buffer(), m_badKeys.buffer(), cl::Local(rows * 4));
    launch(m_count, chunks, "countChunkBuckets");

    scanChunked(m_counts.buffer(), m_counts.buffer(), rows * chunks);

    setArgs(m_scatter, keysIn, valuesIn, cl_uint(n), chunkLen, cl_uint(shift), cl_uint(mask), cl_uint(numBuckets),
            m_counts.buffer(), keysOut, valuesOut, cl::Local(rows * 4));
    launch(m_scatter, chunks, "scatterChunkBuckets");
}

void DevicePrimitives::checkKeys() {
    if (m_boost) {
        m_rt.finish("DevicePrimitives::checkKeys");
        return;
    }
    cl_uint bad = 0;
    m_badKeys.read(m_rt, &bad, 1);
    if (bad) {
        m_badKeys.fill(m_rt, 0u, 1);
        throw btOpenCLSolverError("DevicePrimitives: a key past the sort's key range (maxKeyExclusive or "
                                  "2^keyBits) was passed; the sorted output is not valid");
    }
}

void DevicePrimitives::exclusiveScan(const cl::Buffer& in, const cl::Buffer& out, size_t n) {
    requireBytes(in, n, "exclusiveScan (in)");
    requireBytes(out, n, "exclusiveScan (out)");
    if (n == 0) return;
    if (m_boost) {
        bc::buffer i(in(), true), o(out(), true);
        const std::lock_guard<std::mutex> guard(Boost::lock());
        bc::exclusive_scan(bc::make_buffer_iterator<bc::int_>(i, 0), bc::make_buffer_iterator<bc::int_>(i, n),
                           bc::make_buffer_iterator<bc::int_>(o, 0), m_boost->queue);
        return;
    }
    scanChunked(in, out, n);
}

void DevicePrimitives::scanChunked(const cl::Buffer& in, const cl::Buffer& out, size_t n) {
    const size_t chunks = chunksFor(n, kScanMinChunk);
    const cl_uint chunkLen = cl_uint(ceilDiv(n, chunks));
    if (chunks > 1) {
        setArgs(m_sumChunks, in, cl_uint(n), chunkLen, m_chunkSums.buffer());
        launch(m_sumChunks, chunks, "sumChunks");
    }
    setArgs(m_scanChunks, in, out, cl_uint(n), chunkLen, m_chunkSums.buffer());
    launch(m_scanChunks, chunks, "scanChunks");
}

}  // namespace btocl
