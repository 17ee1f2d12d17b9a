#include "LaneLayout.h"

#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cstddef>
#include <functional>
#include <utility>

namespace btocl {
namespace {

// Lanes are dealt runs of about this many groups where a set has enough: runs of several groups
// even out the lanes' lengths (a slot's lanes all wait for its longest), and fewer bundles
// leave fewer lanes empty.
constexpr int kGroupsPerLane = 3;
constexpr int kPrefetchAhead = 4;

inline void prefetch(const void* p) {
#if defined(__GNUC__)
    __builtin_prefetch(p);
#else
    (void)p;
#endif
}

}  // namespace

bool rowsFitLanes(const btoclRowRegions& regions, int frictionPerPoint) {
    return btoclRegionRows(&regions, BTOCL_ROWS_JOINT) == 0 && btoclRegionRows(&regions, BTOCL_ROWS_ROLLING) == 0 &&
           btoclRegionRows(&regions, BTOCL_ROWS_FRICTION) ==
               frictionPerPoint * btoclRegionRows(&regions, BTOCL_ROWS_NORMAL);
}

void layOutLanes(const BatchLayout& split, const btoclConstraint* constraints, const btoclRowRegions& regions,
                 int lanes, int frictionPerPoint, int minBundlesPerSet, LaneLayout& out) {
    if (lanes < 2 || frictionPerPoint < 1 || !split.serialRuns)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a lane layout needs 2 lanes or more and a serial split");
    const std::size_t W = std::size_t(lanes);
    out.lanes = lanes;
    out.frictionPerPoint = frictionPerPoint;
    out.bundles.clear();
    out.slots.clear();
    out.laneInts.clear();
    out.laneConstraint.clear();
    out.rowMap.assign(std::size_t(regions.start[BTOCL_NUM_ROW_KINDS]), -1);
    out.usedLanes = 0;
    out.usedRowPlaces = 0;
    int normalBlocks = 0, frictionBlocks = 0;  // friction blocks counted from the friction region's start
    // Per run (a lane of a bundle) of the set: its groups, in the split's order, at
    // runGroups[runFirst[r], runFirst[r + 1]).
    std::vector<int> order, runFirst, runGroups, runOf;
    std::vector<long long> runLength;
    std::vector<std::pair<long long, int>> shortest;
    struct Cursor {
        int at, end, position;  // the lane's place in runGroups, its run's end there, the position in the group
    };
    std::vector<Cursor> cursors(W);
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        out.setBundleStart[std::size_t(set)] = int(out.bundles.size());
        const int firstGroup = split.setGroupStart[std::size_t(set)];
        const int groupEnd = split.setGroupStart[std::size_t(set) + 1];
        const int numGroups = groupEnd - firstGroup;
        if (numGroups == 0) continue;
        const int mostBundles = (numGroups + lanes - 1) / lanes;  // one group a lane at least
        const int numBundles = std::max(1, std::min(mostBundles, std::max(minBundlesPerSet, numGroups / (kGroupsPerLane * lanes))));
        const int numRuns = numBundles * lanes;
        // The groups of a set share no dynamic body, so any lane may take any of them: the
        // largest first, each to the run with the fewest constraints so far (the lowest run
        // where they tie), so that the lanes of a bundle and the bundles end together.
        order.resize(std::size_t(numGroups));
        for (int k = 0; k < numGroups; ++k) order[std::size_t(k)] = firstGroup + k;
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
            return split.groups[std::size_t(a)].count > split.groups[std::size_t(b)].count;
        });
        runLength.assign(std::size_t(numRuns), 0);
        runOf.assign(std::size_t(numGroups), 0);
        shortest.clear();  // a min-heap of (constraints, run)
        for (int r = 0; r < numRuns; ++r) shortest.emplace_back(0, r);
        for (const int g : order) {
            std::pop_heap(shortest.begin(), shortest.end(), std::greater<>());
            std::pair<long long, int>& run = shortest.back();
            run.first += split.groups[std::size_t(g)].count;
            runLength[std::size_t(run.second)] = run.first;
            runOf[std::size_t(g - firstGroup)] = run.second;
            std::push_heap(shortest.begin(), shortest.end(), std::greater<>());
        }
        // Each run's groups in the split's order (a counting sort by run).
        runFirst.assign(std::size_t(numRuns) + 1, 0);
        for (int k = 0; k < numGroups; ++k) ++runFirst[std::size_t(runOf[std::size_t(k)]) + 1];
        for (int r = 0; r < numRuns; ++r) runFirst[std::size_t(r) + 1] += runFirst[std::size_t(r)];
        runGroups.resize(std::size_t(numGroups));
        {
            std::vector<int> fill(runFirst.begin(), runFirst.end() - 1);
            for (int k = 0; k < numGroups; ++k)
                runGroups[std::size_t(fill[std::size_t(runOf[std::size_t(k)])]++)] = firstGroup + k;
        }
        for (int b = 0; b < numBundles; ++b) {
            int steps = 0;
            for (std::size_t i = 0; i < W; ++i) {
                const std::size_t r = std::size_t(b) * W + i;
                cursors[i] = Cursor{runFirst[r], runFirst[r + 1], 0};
                steps = std::max(steps, int(runLength[r]));
            }
            out.bundles.push_back(btoclGroup{int(out.slots.size()), steps, 1, -1});
            for (int t = 0; t < steps; ++t) {
                btoclLaneSlot slot{normalBlocks, 0, frictionBlocks, 0};
                const std::size_t ints = out.laneInts.size();
                out.laneInts.resize(ints + BTOCL_LANE_INTS * W, 0);
                for (std::size_t i = 0; i < W; ++i) {
                    Cursor& cur = cursors[i];
                    while (cur.at < cur.end &&
                           cur.position >= split.groups[std::size_t(runGroups[std::size_t(cur.at)])].count) {
                        ++cur.at;
                        cur.position = 0;
                    }
                    if (cur.at >= cur.end) {
                        out.laneConstraint.push_back(-1);
                        continue;
                    }
                    const btoclGroup& g = split.groups[std::size_t(runGroups[std::size_t(cur.at)])];
                    // Constraints lie in gather order, read here in solve order: the lane's record
                    // a few slots ahead asked for (within its group; a group's first few wait).
                    if (cur.position + kPrefetchAhead < g.count)
                        prefetch(constraints + split.solveOrder[std::size_t(g.offset + cur.position + kPrefetchAhead)]);
                    // ... and the row map's entries of the one half as far ahead, whose record is there.
                    if (cur.position + kPrefetchAhead / 2 < g.count) {
                        const btoclConstraint& ahead =
                            constraints[split.solveOrder[std::size_t(g.offset + cur.position + kPrefetchAhead / 2)]];
                        prefetch(out.rowMap.data() + ahead.firstRow[BTOCL_ROWS_NORMAL]);
                        prefetch(out.rowMap.data() + ahead.firstRow[BTOCL_ROWS_FRICTION]);
                    }
                    const int ci = split.solveOrder[std::size_t(g.offset + cur.position++)];
                    const btoclConstraint& c = constraints[ci];
                    const int points = c.numRows[BTOCL_ROWS_NORMAL];
                    if (c.numRows[BTOCL_ROWS_FRICTION] != frictionPerPoint * points || c.numRows[BTOCL_ROWS_ROLLING] != 0 ||
                        c.numRows[BTOCL_ROWS_JOINT] != 0)
                        throw btOpenCLSolverError(
                            "btOpenCLConstraintSolver: a constraint with rows the lanes do not solve was laid out in "
                            "lanes");
                    out.laneInts[ints + BTOCL_LANE_BODY_A * W + i] = c.bodyA;
                    out.laneInts[ints + BTOCL_LANE_BODY_B * W + i] = c.bodyB;
                    out.laneInts[ints + BTOCL_LANE_POINTS * W + i] = points;
                    out.laneInts[ints + BTOCL_LANE_FIRST_POINT * W + i] = c.firstRow[BTOCL_ROWS_NORMAL];
                    out.laneConstraint.push_back(ci);
                    const int lane = int(i);
                    for (int k = 0; k < points; ++k)
                        out.rowMap[std::size_t(c.firstRow[BTOCL_ROWS_NORMAL] + k)] = (normalBlocks + k) * lanes + lane;
                    for (int k = 0; k < points * frictionPerPoint; ++k)
                        out.rowMap[std::size_t(c.firstRow[BTOCL_ROWS_FRICTION] + k)] = (frictionBlocks + k) * lanes + lane;
                    slot.normalBlocks = std::max(slot.normalBlocks, points);
                    out.usedLanes += 1;
                    out.usedRowPlaces += points * (1 + frictionPerPoint);
                }
                slot.frictionBlocks = slot.normalBlocks * frictionPerPoint;
                normalBlocks += slot.normalBlocks;
                frictionBlocks += slot.frictionBlocks;
                out.slots.push_back(slot);
            }
        }
    }
    out.setBundleStart[BTOCL_NUM_SETS + 1] = int(out.bundles.size());
    // The friction region after every normal block.
    for (btoclLaneSlot& slot : out.slots) slot.frictionBlock += normalBlocks;
    const int frictionShift = normalBlocks * lanes;
    for (int r = regions.start[BTOCL_ROWS_FRICTION]; r < regions.start[BTOCL_ROWS_ROLLING]; ++r) {
        out.rowMap[std::size_t(r)] += frictionShift;
    }
    out.numBlocks = normalBlocks + frictionBlocks;
}

std::string validateLaneLayout(const LaneLayout& l, const BatchLayout& split,
                               const std::vector<btoclConstraint>& constraints) {
    const int W = l.lanes;
    if (W < 2) return "fewer than 2 lanes";
    const std::size_t numSlots = l.slots.size();
    if (l.laneInts.size() != numSlots * BTOCL_LANE_INTS * std::size_t(W) || l.laneConstraint.size() != numSlots * std::size_t(W))
        return "a slot's lanes are not W";
    // Where each constraint lies in the split: its set, group and position.
    std::vector<int> setOf(constraints.size(), -1), groupOf(constraints.size(), -1), positionOf(constraints.size(), -1);
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set)
        for (int g = split.setGroupStart[std::size_t(set)]; g < split.setGroupStart[std::size_t(set) + 1]; ++g)
            for (int k = 0; k < split.groups[std::size_t(g)].count; ++k) {
                const std::size_t ci = std::size_t(split.solveOrder[std::size_t(split.groups[std::size_t(g)].offset + k)]);
                setOf[ci] = set;
                groupOf[ci] = g;
                positionOf[ci] = k;
            }
    std::vector<int> seen(constraints.size(), 0);
    std::vector<int> rowOwner(std::size_t(l.numBlocks) * std::size_t(W), -1);
    std::vector<int> bodies;
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        for (int bi = l.setBundleStart[std::size_t(set)]; bi < l.setBundleStart[std::size_t(set) + 1]; ++bi) {
            const btoclGroup& bundle = l.bundles[std::size_t(bi)];
            if (bundle.offset < 0 || bundle.offset + bundle.count > int(numSlots)) return "a bundle past the slots";
            for (int i = 0; i < W; ++i) {
                int lastGroup = -1, lastPosition = -1;
                for (int t = 0; t < bundle.count; ++t) {
                    const std::size_t slot = std::size_t(bundle.offset + t);
                    const int ci = l.laneConstraint[slot * std::size_t(W) + std::size_t(i)];
                    const int* ints = l.laneInts.data() + slot * BTOCL_LANE_INTS * std::size_t(W);
                    if (ci < 0) {
                        if (ints[BTOCL_LANE_POINTS * W + i] != 0) return "an unused lane holds rows";
                        lastGroup = split.setGroupStart[BTOCL_NUM_SETS + 1];  // nothing may follow
                        continue;
                    }
                    const btoclConstraint& c = constraints[std::size_t(ci)];
                    seen[std::size_t(ci)] += 1;
                    if (setOf[std::size_t(ci)] != set) return "a lane holds a constraint of another set";
                    const int g = groupOf[std::size_t(ci)], k = positionOf[std::size_t(ci)];
                    const bool next = g == lastGroup ? k == lastPosition + 1 : g > lastGroup && k == 0 &&
                                      (lastGroup < 0 || lastPosition == split.groups[std::size_t(lastGroup)].count - 1);
                    if (!next) return "a lane does not walk whole groups in their order";
                    lastGroup = g;
                    lastPosition = k;
                    if (ints[BTOCL_LANE_BODY_A * W + i] != c.bodyA || ints[BTOCL_LANE_BODY_B * W + i] != c.bodyB ||
                        ints[BTOCL_LANE_POINTS * W + i] != c.numRows[BTOCL_ROWS_NORMAL] ||
                        ints[BTOCL_LANE_FIRST_POINT * W + i] != c.firstRow[BTOCL_ROWS_NORMAL])
                        return "a lane's ints are not its constraint's";
                    const btoclLaneSlot& s = l.slots[slot];
                    for (int kind : {int(BTOCL_ROWS_NORMAL), int(BTOCL_ROWS_FRICTION)}) {
                        const int firstBlock = kind == BTOCL_ROWS_NORMAL ? s.normalBlock : s.frictionBlock;
                        const int blocks = kind == BTOCL_ROWS_NORMAL ? s.normalBlocks : s.frictionBlocks;
                        if (c.numRows[kind] > blocks) return "a slot has too few blocks for its lanes' rows";
                        for (int r = 0; r < c.numRows[kind]; ++r) {
                            const int at = l.rowMap[std::size_t(c.firstRow[kind] + r)];
                            if (at != (firstBlock + r) * W + i) return "a row is not at its lane and block";
                            if (at < 0 || at >= int(rowOwner.size()) || rowOwner[std::size_t(at)] >= 0)
                                return "two rows share a place";
                            rowOwner[std::size_t(at)] = ci;
                        }
                    }
                }
            }
        }
    }
    for (std::size_t c = 0; c < seen.size(); ++c)
        if (seen[c] != 1) return "a constraint is not in exactly one lane";
    // No dynamic body twice in a slot: the lanes of a slot are solved at once.
    for (std::size_t slot = 0; slot < numSlots; ++slot) {
        bodies.clear();
        for (int i = 0; i < W; ++i) {
            const int ci = l.laneConstraint[slot * std::size_t(W) + std::size_t(i)];
            if (ci < 0) continue;
            for (int side = 0; side < 2; ++side)
                if (dynamicBodyOf(constraints[std::size_t(ci)], side) >= 0)
                    bodies.push_back(dynamicBodyOf(constraints[std::size_t(ci)], side));
        }
        std::sort(bodies.begin(), bodies.end());
        if (std::adjacent_find(bodies.begin(), bodies.end()) != bodies.end()) return "a dynamic body twice in a slot";
    }
    return "";
}

}  // namespace btocl
