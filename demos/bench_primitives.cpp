// Times the device primitives of the global split, hand-written (chunked) against
// Boost.Compute, at the sizes the solver sees. Prints JSON: ms median of `runs` after warm-up,
// each timed from the first enqueue to the end of queue.finish().
//   bench_primitives [runs=9] [keyRange=4096]
#include "CliChecks.h"
#include "DevicePrimitives.h"
#include "DeviceBuffer.h"
#include "OclRuntime.h"

#include <boost/compute/algorithm/detail/radix_sort.hpp>
#include <boost/compute/command_queue.hpp>
#include <boost/compute/iterator/buffer_iterator.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

using namespace btocl;
namespace bc = boost::compute;
using Json = nlohmann::ordered_json;

namespace {

// Milliseconds to the microsecond, so the JSON does not carry meaningless digits.
double roundMs(double ms) { return std::round(ms * 1000) / 1000; }

double medianMs(const OclRuntime& rt, int runs, const std::function<void()>& prepare,
                const std::function<void()>& work) {
    std::vector<double> ms;
    for (int r = -2; r < runs; ++r) {  // two warm-up runs
        prepare();
        rt.finish("prepare");
        const auto t0 = std::chrono::steady_clock::now();
        work();
        rt.finish("work");
        const auto t1 = std::chrono::steady_clock::now();
        if (r >= 0) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 9;
    unsigned keyRange = 4096;
    CLI::App app("Times the device primitives of the global split, hand-written (chunked) against\n"
                 "Boost.Compute, at the sizes the solver sees. Prints JSON: the median of RUNS runs in ms.",
                 "bench_primitives");
    app.add_option("runs", runs, "timed runs per measurement, after two warm-up runs")
        ->type_name("N")
        ->transform(btdemo::integerIn(1, 10000))
        ->capture_default_str();
    app.add_option("keyRange", keyRange, "keys of the small-range sorts are below this")
        ->type_name("K")
        ->transform(btdemo::integerIn(2, long(DevicePrimitives::maxSmallKeyRange())))
        ->capture_default_str();
    if (const std::optional<int> status = btdemo::parseOrExitCode(app, argc, argv, "bench_primitives")) return *status;
    try {
        OclRuntime rt("");
        std::fprintf(stderr, "device: %s; building both backends (Boost.Compute compiles at first use)\n",
                     rt.deviceName().c_str());
        DevicePrimitives chunked(rt, DevicePrimitives::Backend::Chunked);
        DevicePrimitives boost(rt, DevicePrimitives::Backend::BoostCompute);
        bc::command_queue bq(rt.queue()(), true);
        unsigned keyBits = 1;
        while ((1u << keyBits) < keyRange) ++keyBits;

        Json out;
        out["device"] = rt.deviceName();
        out["runs"] = runs;
        out["keyRange"] = keyRange;
        Json sizes = Json::array();
        for (const size_t n : {size_t(10000), size_t(60000), size_t(300000), size_t(1000000)}) {
            std::mt19937 rng{unsigned(n)};
            std::vector<cl_uint> keys(n), wide(n);
            std::vector<cl_int> values(n);
            for (size_t i = 0; i < n; ++i) {
                keys[i] = rng() % keyRange;
                wide[i] = rng();
                values[i] = cl_int(i);
            }
            DeviceBuffer<cl_uint> k0, w0, k;
            DeviceBuffer<cl_int> v0, v;
            k0.write(rt, keys);
            w0.write(rt, wide);
            v0.write(rt, values);
            k.reserve(rt, n);
            v.reserve(rt, n);
            auto restore = [&](const DeviceBuffer<cl_uint>& src) {
                return [&rt, &src, &k, &v, &v0, n] {
                    checkCl(rt.queue().enqueueCopyBuffer(src.buffer(), k.buffer(), 0, 0, n * 4), "restore");
                    checkCl(rt.queue().enqueueCopyBuffer(v0.buffer(), v.buffer(), 0, 0, n * 4), "restore");
                };
            };
            const auto smallKeys = restore(k0), wideKeys = restore(w0);
            auto boostRadix = [&] {
                bc::buffer kb(k.buffer()(), true), vb(v.buffer()(), true);
                bc::detail::radix_sort_by_key(bc::make_buffer_iterator<bc::uint_>(kb, 0),
                                              bc::make_buffer_iterator<bc::uint_>(kb, n),
                                              bc::make_buffer_iterator<bc::int_>(vb, 0), bq);
            };
            std::fprintf(stderr, "n = %zu\n", n);
            const double countSmall = medianMs(rt, runs, smallKeys, [&] {
                chunked.sortByKeySmallRange(k.buffer(), v.buffer(), n, keyRange, false);
            });
            const double radixSmall = medianMs(rt, runs, smallKeys, [&] {
                chunked.sortByKeyBits(k.buffer(), v.buffer(), n, keyBits, false);
            });
            const double radix32Small = medianMs(rt, runs, smallKeys, [&] { chunked.sortByKey(k.buffer(), v.buffer(), n); });
            const double boostSmall = medianMs(rt, runs, smallKeys, [&] { boost.sortByKey(k.buffer(), v.buffer(), n); });
            const double boostRadixSmall = medianMs(rt, runs, smallKeys, boostRadix);
            const double radix32Wide = medianMs(rt, runs, wideKeys, [&] { chunked.sortByKey(k.buffer(), v.buffer(), n); });
            const double boostWide = medianMs(rt, runs, wideKeys, [&] { boost.sortByKey(k.buffer(), v.buffer(), n); });
            const double boostRadixWide = medianMs(rt, runs, wideKeys, boostRadix);
            const double scanChunked = medianMs(rt, runs, [] {}, [&] { chunked.exclusiveScan(v0.buffer(), v.buffer(), n); });
            const double scanBoost = medianMs(rt, runs, [] {}, [&] { boost.exclusiveScan(v0.buffer(), v.buffer(), n); });
            Json size;
            size["n"] = n;
            size["smallKeys_ms"] = {{"chunked_counting", roundMs(countSmall)},
                                    {"chunked_radix_" + std::to_string(keyBits) + "bits", roundMs(radixSmall)},
                                    {"chunked_radix_32bits", roundMs(radix32Small)},
                                    {"boost_stable_sort_by_key", roundMs(boostSmall)},
                                    {"boost_radix", roundMs(boostRadixSmall)}};
            size["randomUint32Keys_ms"] = {{"chunked_radix_32bits", roundMs(radix32Wide)},
                                           {"boost_stable_sort_by_key", roundMs(boostWide)},
                                           {"boost_radix", roundMs(boostRadixWide)}};
            size["exclusiveScan_ms"] = {{"chunked", roundMs(scanChunked)}, {"boost", roundMs(scanBoost)}};
            sizes.push_back(std::move(size));
        }
        out["sizes"] = std::move(sizes);
        std::printf("%s\n", out.dump(2, ' ', false, Json::error_handler_t::replace).c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_primitives: %s\n", e.what());
        return 1;
    }
    return 0;
}
