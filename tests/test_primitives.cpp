// Device sort by key and exclusive scan against std::stable_sort and std::exclusive_scan, for
// both backends. Results must match exactly: integer data, stable sort, deterministic kernels.
#include "DeviceBuffer.h"
#include "DevicePrimitives.h"
#include "OclRuntime.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

using namespace btocl;
using Backend = DevicePrimitives::Backend;

namespace {

// One runtime and one DevicePrimitives per backend for the whole test program: Boost.Compute
// compiles its kernels once per context (seconds on PoCL).
struct Fixture {
    OclRuntime rt{""};
    std::unique_ptr<DevicePrimitives> chunked, boost;
    DevicePrimitives& get(Backend b) {
        auto& p = b == Backend::Chunked ? chunked : boost;
        if (!p) p = std::make_unique<DevicePrimitives>(rt, b);
        return *p;
    }
};
Fixture& fixture() {
    static Fixture f;
    return f;
}

struct Pairs {
    std::vector<cl_uint> keys;
    std::vector<cl_int> values;
};

// Values are the original positions, so a stable sort has exactly one right answer.
Pairs makePairs(size_t n, cl_uint keyRange, unsigned seed) {
    std::mt19937 rng(seed);
    Pairs p;
    p.keys.resize(n);
    p.values.resize(n);
    for (size_t i = 0; i < n; ++i) {
        p.keys[i] = keyRange ? cl_uint(rng() % keyRange) : cl_uint(rng());
        p.values[i] = cl_int(i);
    }
    return p;
}

Pairs hostStableSort(const Pairs& in) {
    std::vector<size_t> order(in.keys.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return in.keys[a] < in.keys[b]; });
    Pairs out;
    for (size_t i : order) {
        out.keys.push_back(in.keys[i]);
        out.values.push_back(in.values[i]);
    }
    return out;
}

enum class Sort { ByKey, SmallRange };

Pairs deviceSort(DevicePrimitives& prims, const Pairs& in, Sort sort, cl_uint keyRange) {
    OclRuntime& rt = fixture().rt;
    DeviceBuffer<cl_uint> k;
    DeviceBuffer<cl_int> v;
    k.write(rt, in.keys);
    v.write(rt, in.values);
    k.reserve(rt, 1);  // an empty input still needs a buffer to name
    v.reserve(rt, 1);
    if (sort == Sort::ByKey)
        prims.sortByKey(k.buffer(), v.buffer(), in.keys.size());
    else
        prims.sortByKeySmallRange(k.buffer(), v.buffer(), in.keys.size(), keyRange);
    return Pairs{k.read(rt, in.keys.size()), v.read(rt, in.keys.size())};
}

}  // namespace

TEST_CASE("sortByKey and sortByKeySmallRange match std::stable_sort", "[primitives]") {
    const Backend backend = GENERATE(Backend::Chunked, Backend::BoostCompute);
    const Sort sort = GENERATE(Sort::ByKey, Sort::SmallRange);
    DevicePrimitives& prims = fixture().get(backend);
    struct Case {
        size_t n;
        cl_uint keyRange;  // 0 = any 32-bit key (sortByKey only)
    };
    // 1000 equal keys; 1e6 cell-like keys; few distinct keys; a range past local memory.
    std::vector<Case> cases = {{0, 4096}, {1, 4096}, {1000, 1}, {1000000, 4096}, {60000, 3}, {100000, 1u << 20}};
    if (sort == Sort::ByKey) cases.push_back({1000000, 0});
    for (const Case& c : cases) {
        INFO("backend " << prims.backendName() << ", " << (sort == Sort::ByKey ? "sortByKey" : "sortByKeySmallRange")
                        << ", n " << c.n << ", key range " << c.keyRange);
        const Pairs in = makePairs(c.n, c.keyRange, unsigned(c.n + c.keyRange));
        const Pairs want = hostStableSort(in);
        const Pairs got = deviceSort(prims, in, sort, c.keyRange);
        CHECK(got.keys == want.keys);
        CHECK(got.values == want.values);
    }
}

TEST_CASE("the chunked sort gives bitwise the same output every run", "[primitives]") {
    DevicePrimitives& prims = fixture().get(Backend::Chunked);
    const Pairs in = makePairs(300000, 5000, 7);
    const Pairs first = deviceSort(prims, in, Sort::SmallRange, 5000);
    for (int run = 0; run < 3; ++run) {
        const Pairs again = deviceSort(prims, in, Sort::SmallRange, 5000);
        CHECK(again.keys == first.keys);
        CHECK(again.values == first.values);
    }
}

TEST_CASE("exclusiveScan matches std::exclusive_scan, also in place", "[primitives]") {
    const Backend backend = GENERATE(Backend::Chunked, Backend::BoostCompute);
    DevicePrimitives& prims = fixture().get(backend);
    OclRuntime& rt = fixture().rt;
    for (size_t n : {size_t(0), size_t(1), size_t(1000), size_t(1000000)}) {
        INFO("backend " << prims.backendName() << ", n " << n);
        std::mt19937 rng{unsigned(n)};
        std::vector<cl_int> in(n);
        for (cl_int& x : in) x = cl_int(rng() % 2001) - 1000;  // sums stay far from overflow
        std::vector<cl_int> want(n);
        std::exclusive_scan(in.begin(), in.end(), want.begin(), 0);

        DeviceBuffer<cl_int> a, b;
        a.write(rt, in);
        a.reserve(rt, 1);
        b.reserve(rt, std::max<size_t>(n, 1));
        prims.exclusiveScan(a.buffer(), b.buffer(), n);
        CHECK(b.read(rt, n) == want);
        CHECK(a.read(rt, n) == in);  // input untouched
        prims.exclusiveScan(a.buffer(), a.buffer(), n);
        CHECK(a.read(rt, n) == want);
    }
}

TEST_CASE("bad input to the primitives gets a clear error", "[primitives]") {
    DevicePrimitives& prims = fixture().get(Backend::Chunked);
    OclRuntime& rt = fixture().rt;
    DeviceBuffer<cl_uint> k, v;
    k.write(rt, std::vector<cl_uint>{1, 2, 70, 3});
    v.write(rt, std::vector<cl_uint>{0, 1, 2, 3});

    // A key past the range: never an out-of-bounds write, and the check names the problem.
    CHECK_THROWS_WITH(prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, 10),
                      Catch::Contains("past the sort's key range"));
    // The flag is cleared by the throw: a good call afterwards passes.
    k.write(rt, std::vector<cl_uint>{1, 2, 7, 3});
    CHECK_NOTHROW(prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, 10));
    CHECK(k.read(rt, 4) == std::vector<cl_uint>{1, 2, 3, 7});

    // Deferred check: the sort enqueues only; checkKeys reports.
    k.write(rt, std::vector<cl_uint>{1, 2, 70, 3});
    prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, 10, false);
    CHECK_THROWS_AS(prims.checkKeys(), btOpenCLSolverError);

    // The same through the radix path taken when the range does not fit local memory.
    const unsigned wide = DevicePrimitives::maxSmallKeyRange();
    k.write(rt, std::vector<cl_uint>{1, 2, wide + 5, 3});
    CHECK_THROWS_WITH(prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, wide),
                      Catch::Contains("past the sort's key range"));
    k.write(rt, std::vector<cl_uint>{9, wide - 1, 0, 3});
    CHECK_NOTHROW(prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, wide));
    CHECK(k.read(rt, 4) == std::vector<cl_uint>{0, 3, 9, wide - 1});

    CHECK_THROWS_WITH(prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, 0), Catch::Contains("maxKeyExclusive"));
    CHECK_THROWS_WITH(prims.sortByKeySmallRange(k.buffer(), v.buffer(), 4, wide + 1),
                      Catch::Contains("maxKeyExclusive"));
    CHECK_THROWS_WITH(prims.sortByKey(k.buffer(), v.buffer(), 1u << 20), Catch::Contains("cannot hold"));
    CHECK_THROWS_WITH(prims.exclusiveScan(k.buffer(), cl::Buffer(), 4), Catch::Contains("cannot hold"));
    CHECK_THROWS_AS(prims.sortByKeyBits(k.buffer(), v.buffer(), 4, 33), btOpenCLSolverError);
}

TEST_CASE("timeBackends keeps the backend that did the split's work faster, measured once per device",
          "[primitives]") {
    const OclRuntime& rt = fixture().rt;
    const DevicePrimitives::BackendTiming first = DevicePrimitives::timeBackends(rt);
    INFO("chunked " << first.msChunked << " ms, boost.compute " << first.msBoostCompute << " ms");
    CHECK(first.msChunked > 0);
    CHECK(first.msBoostCompute > 0);
    CHECK(first.faster == (first.msChunked <= first.msBoostCompute ? Backend::Chunked : Backend::BoostCompute));
    // Remembered: a second solver on the device pays nothing and gets the same choice.
    const DevicePrimitives::BackendTiming again = DevicePrimitives::timeBackends(rt);
    CHECK(again.msChunked == first.msChunked);
    CHECK(again.msBoostCompute == first.msBoostCompute);
    CHECK(DevicePrimitives::fasterBackend(rt) == first.faster);
    // A separate runtime on the same device shares the measurement.
    OclRuntime other{""};
    CHECK(DevicePrimitives::timeBackends(other).msChunked == first.msChunked);
}

TEST_CASE("Boost.Compute's cached programs let a context go with the last DevicePrimitives on it", "[primitives]") {
    // Its process-wide program cache kept every context it had built for (up to eight), and
    // with it the context's memory, long after the solver was gone.
    OclRuntime rt{""};
    const auto references = [&] { return rt.context().getInfo<CL_CONTEXT_REFERENCE_COUNT>(); };
    const cl_uint before = references();
    {
        DevicePrimitives first(rt, Backend::BoostCompute);
        DevicePrimitives second(rt, Backend::BoostCompute);
    }
    CHECK(references() == before);
}
