// The host's loops over bodies, manifolds and points, spread over the host's cores with OpenMP
// (libgomp, which comes with g++: no other package, and no thread pool of our own to keep).
// Every loop writes only its own item's records, so the result is the serial loop's, bitwise.
#pragma once

#include <cstddef>
#include <exception>
#include <limits>

namespace btocl {

// Below this many items a loop runs on the calling thread. After a parallel region libgomp's
// threads spin-wait for more work (unless OMP_WAIT_POLICY=passive), on the cores where PoCL's
// threads then run the step's kernels: a pyramid of 2,360 contact points took 1.34 ms a step with
// its write-back in parallel, 1.10 ms with passive threads (PoCL, 2 cores). From about 16K items
// the loops' gain outweighs that (block 12K: gather 30 -> 20 ms, write-back 7.7 -> 3.9 ms).
// Tests lower it to run small scenes in parallel, and raise it to run large ones serially.
constexpr size_t kMinParallelItems = 16384;
inline size_t& minParallelItems() {
    static size_t items = kMinParallelItems;
    return items;
}

// Calls f(i) for every i in [0, n): in parallel from minParallelItems() on, counting each item
// as `weight` (an item that costs as much as several of a manifold loop's). An exception thrown
// by f leaves the loop: the one of the lowest index, as the serial loop would have thrown first.
template <class F>
void parallelFor(size_t n, F&& f, size_t weight = 1) {
    if (n * weight < minParallelItems()) {
        for (size_t i = 0; i < n; ++i) f(i);
        return;
    }
    std::exception_ptr error;
    size_t errorAt = std::numeric_limits<size_t>::max();
#pragma omp parallel for schedule(static)
    for (long long i = 0; i < static_cast<long long>(n); ++i) {
        try {
            f(static_cast<size_t>(i));
        } catch (...) {
#pragma omp critical(btocl_parallel_for_error)
            if (static_cast<size_t>(i) < errorAt) {
                errorAt = static_cast<size_t>(i);
                error = std::current_exception();
            }
        }
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace btocl
