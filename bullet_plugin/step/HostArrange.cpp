#include "HostArrange.h"

#include "HostArray.h"

#include <cstddef>

namespace btocl {

void arrangeOnHost(const int* solveOrder, const btoclConstraint* constraints, int n, const btoclRowRegions& regions,
                   HostArrangement& out) {
    resizeForOverwrite(out.placed, std::size_t(n));
    resizeForOverwrite(out.rowMap, std::size_t(regions.start[BTOCL_NUM_ROW_KINDS]));
    int next[2] = {0, btoclFrictionRegionStart(&regions)};
    for (int i = 0; i < n; ++i) {
        btoclConstraint c = constraints[solveOrder[i]];
        for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind) {
            int& at = next[btoclInFrictionRegion(kind)];
            for (int k = 0; k < c.numRows[kind]; ++k) out.rowMap[std::size_t(c.firstRow[kind] + k)] = at + k;
            c.firstRow[kind] = at;
            at += c.numRows[kind];
        }
        out.placed[std::size_t(i)] = c;
    }
}

}  // namespace btocl
