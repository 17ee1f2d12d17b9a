// The invariants of a split and batch layout (docs/architecture.md, "Invariants"), checked on the host. The solver runs
// it every step when btOpenCLSolverConfig::validate is set; the tests run it on their layouts.
#pragma once

#include "BatchLayout.h"

#include <string>
#include <vector>

namespace btocl {

// Every constraint exactly once; groups tile the solve order and batches tile each group; no
// dynamic body in two groups of one set; no dynamic body twice in one batch (unless the layout is
// the serial path's, whose groups are one run each).
// Returns "" or the first failure.
std::string validateBatchLayout(const BatchLayout& layout, const std::vector<btoclConstraint>& constraints);

}  // namespace btocl
