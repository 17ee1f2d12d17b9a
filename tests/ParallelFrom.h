// Runs the host's loops (HostParallel.h) in parallel from `minItems` items on for a scope, and
// puts the threshold back after: tests lower it to run small scenes' loops on the pool.
#pragma once

#include "HostParallel.h"

#include <cstddef>

namespace btocl::test {

struct ParallelFrom {
    explicit ParallelFrom(size_t minItems) { minParallelItems() = minItems; }
    ~ParallelFrom() { minParallelItems() = kMinParallelItems; }
    ParallelFrom(const ParallelFrom&) = delete;
    ParallelFrom& operator=(const ParallelFrom&) = delete;
};

}  // namespace btocl::test
