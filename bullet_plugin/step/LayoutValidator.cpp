#include "LayoutValidator.h"

#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace btocl {

std::string validateBatchLayout(const BatchLayout& layout, const std::vector<btoclConstraint>& constraints) {
    std::ostringstream err;
    const int n = int(constraints.size());
    if (int(layout.solveOrder.size()) != n) {
        err << "solveOrder holds " << layout.solveOrder.size() << " entries for " << n << " constraints";
        return err.str();
    }
    std::vector<char> seen(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
        const int c = layout.solveOrder[size_t(i)];
        if (c < 0 || c >= n) {
            err << "solveOrder[" << i << "] = " << c << " is not a constraint index";
            return err.str();
        }
        if (seen[size_t(c)]++) {
            err << "constraint " << c << " appears twice in solveOrder (again at " << i << ")";
            return err.str();
        }
    }
    const auto& sgs = layout.setGroupStart;
    if (sgs[0] != 0 || sgs[BTOCL_NUM_SETS + 1] != int(layout.groups.size())) {
        err << "setGroupStart runs from " << sgs[0] << " to " << sgs[BTOCL_NUM_SETS + 1] << " for "
            << layout.groups.size() << " groups";
        return err.str();
    }
    for (int s = 0; s <= BTOCL_NUM_SETS; ++s)
        if (sgs[size_t(s)] > sgs[size_t(s) + 1]) {
            err << "setGroupStart decreases at set " << s;
            return err.str();
        }
    // Groups tile solveOrder in order; batches tile each group.
    int expectedOffset = 0;
    for (size_t gi = 0; gi < layout.groups.size(); ++gi) {
        const btoclGroup& g = layout.groups[gi];
        if (g.offset != expectedOffset || g.count < 1 || g.offset + g.count > n) {
            err << "group " << gi << " (offset " << g.offset << ", count " << g.count
                << ") does not continue the previous group at " << expectedOffset;
            return err.str();
        }
        expectedOffset += g.count;
        if (g.numBatches < 1 || g.numBatches > g.count || size_t(g.offset + g.numBatches) > layout.batchEnd.size()) {
            err << "group " << gi << " has " << g.numBatches << " batches for " << g.count << " constraints";
            return err.str();
        }
        int begin = g.offset;
        for (int k = 0; k < g.numBatches; ++k) {
            const int end = layout.batchEnd[size_t(g.offset + k)];
            if (end <= begin || end > g.offset + g.count) {
                err << "group " << gi << " batch " << k << " ends at " << end << " after starting at " << begin;
                return err.str();
            }
            if (!layout.serialRuns) {
                std::unordered_set<int> inBatch;
                for (int i = begin; i < end; ++i) {
                    const btoclConstraint& c = constraints[size_t(layout.solveOrder[size_t(i)])];
                    for (int side = 0; side < 2; ++side) {
                        const int body = dynamicBodyOf(c, side);
                        if (body < 0) continue;
                        if (side == 1 && c.dynamicA && c.bodyA == body) continue;  // a pair with itself
                        if (!inBatch.insert(body).second) {
                            err << "dynamic body " << body << " appears twice in batch " << k << " of group " << gi;
                            return err.str();
                        }
                    }
                }
            }
            begin = end;
        }
        if (begin != g.offset + g.count) {
            err << "the batches of group " << gi << " end at " << begin << ", not at its end " << g.offset + g.count;
            return err.str();
        }
    }
    if (expectedOffset != n) {
        err << "the groups cover " << expectedOffset << " of " << n << " constraints";
        return err.str();
    }
    // Groups of one set run at the same time: no dynamic body may be in two of them.
    for (int s = 0; s <= BTOCL_NUM_SETS; ++s) {
        std::unordered_map<int, int> groupOfBody;
        for (int gi = sgs[size_t(s)]; gi < sgs[size_t(s) + 1]; ++gi) {
            const btoclGroup& g = layout.groups[size_t(gi)];
            for (int i = g.offset; i < g.offset + g.count; ++i) {
                const btoclConstraint& c = constraints[size_t(layout.solveOrder[size_t(i)])];
                for (int side = 0; side < 2; ++side) {
                    const int body = dynamicBodyOf(c, side);
                    if (body < 0) continue;
                    auto [it, inserted] = groupOfBody.emplace(body, gi);
                    if (!inserted && it->second != gi) {
                        err << "dynamic body " << body << " is in groups " << it->second << " and " << gi << " of set "
                            << s;
                        return err.str();
                    }
                }
            }
        }
    }
    return "";
}

}  // namespace btocl
