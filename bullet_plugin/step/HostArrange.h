// The constraints placed in solve order with their rows' new places (the host twin of
// kernels/arrange.cl's countRowsInSolveOrder, the scans and placeConstraints), for a step whose
// split the host made (HostSplit.h): a CPU device would spend more on those launches than on the
// work. Equal to the device's to the bit (tests/test_device_solve.cpp).
#pragma once

#include "btocl_shared.h"

#include <vector>

namespace btocl {

struct HostArrangement {
    std::vector<btoclConstraint> placed;  // constraint solveOrder[i] at i, its rows' first places in solve order
    std::vector<int> rowMap;              // per row in gather order: its place in solve order
};

// Rows of the first region (normal and joint rows) in solve order from 0, those of the second
// (friction and rolling) from the region's start, each constraint's of a kind together.
void arrangeOnHost(const int* solveOrder, const btoclConstraint* constraints, int n, const btoclRowRegions& regions,
                   HostArrangement& out);

}  // namespace btocl
