// The layout that reproduces btSequentialImpulseConstraintSolver's order on the device: one
// group, one constraint per batch, constraints in gather order. Not parallel: the tests use it
// to hold the device rows and iterations to SI's own operation order.
#pragma once

#include "BatchLayout.h"

namespace btocl {

inline BatchLayout buildSerialLayout(int numConstraints) {
    BatchLayout layout;
    layout.solveOrder.resize(size_t(numConstraints));
    layout.batchEnd.resize(size_t(numConstraints));
    for (int i = 0; i < numConstraints; ++i) {
        layout.solveOrder[size_t(i)] = i;
        layout.batchEnd[size_t(i)] = i + 1;
    }
    if (numConstraints > 0) layout.groups.push_back(btoclGroup{0, numConstraints, numConstraints, 0});
    layout.setGroupStart.fill(int(layout.groups.size()));
    layout.setGroupStart[0] = 0;
    return layout;
}

}  // namespace btocl
