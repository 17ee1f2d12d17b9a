// What this machine's cores can move, for the solve's limit (docs/performance.md, "How far from
// the hardware"): read and copy bandwidth of arrays far larger than the caches, with 1 thread and
// with one thread per core, plus the sizes of the records one row update reads and writes. Prints
// JSON.
//   memory_bandwidth [--mib N] [--runs R]
#include "btocl_shared.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <string>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

using Json = nlohmann::ordered_json;

namespace {

using Clock = std::chrono::steady_clock;

// Runs work(thread, begin, end) on `threads` threads over [0, n) in equal slices; returns seconds.
template <class Work>
double timedOnThreads(int threads, size_t n, Work work) {
    std::vector<std::thread> pool;
    const auto t0 = Clock::now();
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([=] { work(t, n * size_t(t) / size_t(threads), n * size_t(t + 1) / size_t(threads)); });
    for (std::thread& th : pool) th.join();
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The best of `runs` (the machine's other work only ever slows a run down), in GB/s.
template <class Run>
double bestGBps(int runs, double bytes, Run run) {
    double best = 0;
    for (int r = 0; r < runs; ++r) best = std::max(best, bytes / run() / 1e9);
    return std::round(best * 100) / 100;
}

// Data and unified caches of the first core as Linux lists them (level -> KiB); empty elsewhere.
Json cachesKiB() {
    Json caches = Json::object();
    for (int index = 0; index < 8; ++index) {
        const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/";
        std::ifstream level(dir + "level"), type(dir + "type"), size(dir + "size");
        int l = 0;
        std::string t, sz;
        if (!(level >> l) || !(type >> t) || !(size >> sz) || t == "Instruction") continue;
        const double kib = std::stod(sz) * (sz.back() == 'M' ? 1024.0 : 1.0);
        caches["L" + std::to_string(l)] = kib;
    }
    return caches;
}

}  // namespace

int main(int argc, char** argv) {
    int mib = 512, runs = 5;
    CLI::App app("Read and copy bandwidth of large arrays, 1 thread and one per core, as JSON.", "memory_bandwidth");
    app.add_option("--mib", mib, "size of each array in MiB (default 512)")->check(CLI::Range(16, 8192));
    app.add_option("--runs", runs, "runs per figure; the best is kept (default 5)")->check(CLI::Range(1, 100));
    CLI11_PARSE(app, argc, argv);

    const size_t n = size_t(mib) * 1024 * 1024 / sizeof(float);
    std::vector<float> a(n, 1.0f), b(n, 0.0f);  // written once: no page faults in the timed runs
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<double> sums(size_t(cores), 0.0);

    Json out;
    out["threadsPerCore"] = Json::array();
    for (int threads : {1, cores}) {
        // Thirty-two independent sums (four vectors of eight), so that the adds' latency does
        // not bound the loop: eight sums made one vector, whose adds waited on each other.
        const double readGBps = bestGBps(runs, double(n) * sizeof(float), [&] {
            return timedOnThreads(threads, n, [&](int t, size_t begin, size_t end) {
                float s[32] = {0};
                size_t i = begin;
                for (; i + 32 <= end; i += 32)
                    for (int k = 0; k < 32; ++k) s[k] += a[i + size_t(k)];
                for (; i < end; ++i) s[0] += a[i];
                double total = 0;
                for (float v : s) total += v;
                sums[size_t(t)] += total;
            });
        });
        const double copyGBps = bestGBps(runs, 2.0 * double(n) * sizeof(float), [&] {
            return timedOnThreads(threads, n, [&](int, size_t begin, size_t end) {
                std::copy(a.begin() + long(begin), a.begin() + long(end), b.begin() + long(begin));
            });
        });
        out["threadsPerCore"].push_back({{"threads", threads}, {"readGBps", readGBps}, {"copyGBps", copyGBps}});
    }
    out["cores"] = cores;
    out["cacheKiB"] = cachesKiB();
    out["arrayMiB"] = mib;
    // What one row update touches (kernels/btocl_shared.h, kernels/row_solve.h).
    out["bytes"] = {{"solveRow", sizeof(btoclSolveRow)},
                    {"appliedImpulse", sizeof(float)},
                    {"body", sizeof(btoclBody)},
                    {"bodyDelta", sizeof(btoclBodyDelta)},
                    {"constraint", sizeof(btoclConstraint)}};
    // Keeps the sums alive, so that the reads are not optimised away.
    double check = 0;
    for (double s : sums) check += s;
    out["checksum"] = check > 0 ? 1 : 0;
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
