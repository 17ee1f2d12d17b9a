// The host's loops over bodies, manifolds and points, spread over the host's cores by a small pool
// of threads that sleep between loops. Every loop writes only its own item's records, so the
// result is the serial loop's, bitwise.
//
// Why not OpenMP: after a parallel region libgomp's threads spin-wait for more work (unless the
// user sets OMP_WAIT_POLICY=passive, read once at load time), and the step's next thing is the
// device's work, which on PoCL runs on those same cores and lost a fifth of its speed to them
// (docs/performance.md).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>

namespace btocl {

// Below this many items a loop runs on the calling thread (waking the pool costs some tens of
// microseconds, and the items of a small loop take less). From about 16K items the loops' gain
// outweighs that (docs/performance.md); while the pool waits awake, from an eighth of it
// (kAwakeThresholdDivisor).
// Tests lower it to run small scenes in parallel, and raise it to run large ones serially
// (atomic: solvers in other threads read it meanwhile).
constexpr size_t kMinParallelItems = 16384;
inline std::atomic<size_t>& minParallelItems() {
    static std::atomic<size_t> items{kMinParallelItems};
    return items;
}

// The threads a parallel loop runs on, the calling one included (the host's hardware threads).
int hostThreads();

// Asks for every cache line that [begin, begin + bytes) touches: a loop over records scattered in
// memory calls it a few items ahead. forWrite: the loop will write them.
inline void prefetchBytes(const void* begin, size_t bytes, bool forWrite = false) {
    constexpr uintptr_t kLine = 64;
    const uintptr_t first = reinterpret_cast<uintptr_t>(begin) & ~(kLine - 1);
    const uintptr_t end = reinterpret_cast<uintptr_t>(begin) + bytes;
    for (uintptr_t line = first; line < end; line += kLine) {
        const char* at = reinterpret_cast<const char*>(line);
        if (forWrite)
            __builtin_prefetch(at, 1);
        else
            __builtin_prefetch(at);
    }
}

// Wakes the pool's threads ahead of loops to come: each waits awake for the next loop, and
// after each loop for the one after, up to `spin`, then sleeps again. A core that has idled a
// while (a VM's, above all) takes milliseconds to wake, and a loop that starts meanwhile runs on
// the calling thread alone. restHostThreads ends the wait early (the loops are over, and the
// cores are wanted for other work).
void prewakeHostThreads(std::chrono::microseconds spin);
void restHostThreads();
// Whether the pool's threads wait awake (within a pre-wake's deadline).
bool hostThreadsAwake();

// While the pool waits awake a loop costs no wake-up, and smaller loops pay: the threshold is
// divided by this (docs/performance.md, "The host's loops").
constexpr size_t kAwakeThresholdDivisor = 8;

// Runs chunk(c) for c in [0, numChunks) over the pool's threads, the calling thread taking part,
// and returns when every chunk has run. One loop at a time: a second caller (another thread, or
// a chunk itself) runs its chunks on its own thread. chunk must not throw.
void runChunks(int numChunks, void (*chunk)(void* context, int c), void* context);

// Stores past the caches (LaneRowSetup.cpp's streamed rows, the gather's point records) are
// ordered by no lock: a thread that made some drains them before another may read what they
// wrote. The pool's threads drain theirs as they finish their chunks of a loop; a caller drains
// what it stored itself.
void drainStreamedStores();
// From this size on, an array that a step writes whole and reads later is stored past the caches:
// it outgrows the caches near the cores, so its reader finds it in memory either way, and a line
// written whole need not be read first (docs/performance.md, "Lane rows asked for ahead and
// streamed").
constexpr size_t kStreamedArrayBytes = size_t(8) << 20;

// The threads a loop of n items of `weight` would run on (parallelFor's rule, the pool awake).
inline int threadsForLoop(size_t n, size_t weight) {
    return n * weight >= minParallelItems() / kAwakeThresholdDivisor ? hostThreads() : 1;
}

// Runs steps one after another, each in `shares` parts that touch nothing of each other's
// (part(context, step, share)), over up to `shares` of the pool's threads: thread i takes share i
// of every step (so what a share works on stays in its core's cache from step to step), and
// starts a step once every part of the steps before has run. A part still untaken once a thread
// has run its own is run by that thread (a worker that has not come yet, or was taken off its
// core before its part). With onPool false, or the pool taken, every part on the calling thread.
// part must not throw.
void runSharedSteps(int numSteps, int shares, bool onPool, void (*part)(void* context, int step, int share),
                    void* context);

template <class F>
void shareSteps(int numSteps, int shares, bool onPool, F&& part) {
    runSharedSteps(numSteps, shares, onPool, [](void* context, int step, int share) {
        (*static_cast<F*>(context))(step, share);
    }, &part);
}

// What an item weighs in a loop, against the lightest loops' items (weight 1):
// (the counts below are with the pool asleep; an eighth of them where it waits awake)
// a manifold counted or packed by the gather, whose lines lie scattered in memory (from about
// 5,500 manifolds a step those loops run in parallel; docs/performance.md);
constexpr size_t kManifoldWeight = 3;
// a rigid body's record read or written, which costs more than a manifold's packing;
constexpr size_t kRigidBodyWeight = 4;
// a joint's getInfo1 or getInfo2 and its rows: from about 1,000 joints a step their loops run in
// parallel; below that, waking the pool cost more than it saved (docs/performance.md);
constexpr size_t kJointWeight = 16;
// a manifold's contact rows set up on the host (up to four points, three rows each): from about
// 512 such constraints a step their loop runs in parallel, from 64 where the pool was woken
// ahead (a split step on the host; docs/performance.md).
constexpr size_t kContactConstraintWeight = 32;

// Calls f(i) for every i in [0, n): in parallel from minParallelItems() on (an eighth of it while
// the pool waits awake), counting each item as `weight` (the constants above). The items are
// split in contiguous ranges, eight per thread, which the threads take as they come, so that a
// worker that wakes late still takes a share (on a VM a worker can wake after the caller has
// finished a whole loop alone). An exception thrown by f ends its range: the loop rethrows the
// one of the lowest index, as the serial loop would have thrown first.
template <class F>
void parallelFor(size_t n, F&& f, size_t weight = 1) {
    const size_t threads = size_t(hostThreads());
    const size_t items = n * weight;
    if (items < minParallelItems() / kAwakeThresholdDivisor || threads < 2 ||
        (items < minParallelItems() && !hostThreadsAwake())) {
        for (size_t i = 0; i < n; ++i) f(i);
        return;
    }
    struct Loop {
        F& f;
        size_t n, chunks;
        std::exception_ptr errors[64];  // the first of each range
    } loop{f, n, threads * 8 < 64 ? threads * 8 : 64, {}};
    runChunks(int(loop.chunks), [](void* context, int c) {
        Loop& l = *static_cast<Loop*>(context);
        const size_t begin = l.n * size_t(c) / l.chunks, end = l.n * size_t(c + 1) / l.chunks;
        for (size_t i = begin; i < end; ++i) {
            try {
                l.f(i);
            } catch (...) {
                l.errors[c] = std::current_exception();
                return;
            }
        }
    }, &loop);
    for (size_t c = 0; c < loop.chunks; ++c)  // ranges in order: the first error is the lowest
        if (loop.errors[c]) std::rethrow_exception(loop.errors[c]);
}

}  // namespace btocl
