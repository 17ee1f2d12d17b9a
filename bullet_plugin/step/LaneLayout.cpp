#include "LaneLayout.h"

#include "HostArray.h"
#include "HostParallel.h"
#include "HostSplit.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cstdint>
#include <cstddef>
#include <functional>
#include <utility>

namespace btocl {
namespace {

constexpr int kPrefetchAhead = 4;

inline void prefetch(const void* p) {
#if defined(__GNUC__)
    __builtin_prefetch(p);
#else
    (void)p;
#endif
}

}  // namespace

bool contactRowsFitLanes(const btoclRowRegions& regions, int frictionPerPoint) {
    return btoclRegionRows(&regions, BTOCL_ROWS_ROLLING) == 0 &&
           btoclRegionRows(&regions, BTOCL_ROWS_FRICTION) == frictionPerPoint * btoclRegionRows(&regions, BTOCL_ROWS_NORMAL);
}

bool rowsFitLanes(const btoclRowRegions& regions, int frictionPerPoint) {
    return btoclRegionRows(&regions, BTOCL_ROWS_JOINT) == 0 && contactRowsFitLanes(regions, frictionPerPoint);
}

namespace {

// A group of a bundle: its first place in the solve order, its constraints.
struct GroupSpan {
    int offset, count;
};

// The constraints' records by solve order, read ahead of the slots on the host's threads: a loop
// of independent loads waits on the scattered records far less than the slots, whose choices
// wait on each. Throws btOpenCLSolverError for a constraint the lanes do not solve.
void readLaneRecords(const BatchLayout& split, const btoclConstraint* constraints, int frictionPerPoint,
                     std::vector<LaneRecord>& records) {
    resizeForOverwrite(records, split.solveOrder.size());
    parallelFor(records.size(), [&](std::size_t k) {
        const int ci = split.solveOrder[k];
        const btoclConstraint& c = constraints[ci];
        const int points = c.numRows[BTOCL_ROWS_NORMAL];
        if (c.numRows[BTOCL_ROWS_FRICTION] != frictionPerPoint * points || c.numRows[BTOCL_ROWS_ROLLING] != 0 ||
            c.numRows[BTOCL_ROWS_JOINT] != 0)
            throw btOpenCLSolverError(
                "btOpenCLConstraintSolver: a constraint with rows the lanes do not solve was laid out in lanes");
        records[k] = LaneRecord{ci, c.bodyA, c.bodyB, points, c.firstRow[BTOCL_ROWS_NORMAL],
                                c.firstRow[BTOCL_ROWS_FRICTION], dynamicBodyOf(c, 0), dynamicBodyOf(c, 1)};
    }, kManifoldWeight);
}

// One bundle: its groups, then its slots as scheduleBundle chose them (each slot's W lanes as
// places in the solve order, -1 where empty, and its normal blocks), then where its slots and
// blocks begin in the layout. Bundles are scheduled apart and written apart, in parallel; only
// the running counts between them are serial.
struct BundlePlan {
    int firstGroup = 0, endGroup = 0;
    std::vector<int> lanes;
    std::vector<int> normalBlocks;
    int firstSlot = 0, firstNormalBlock = 0;
};

// A bundle's slots from its constraints. A constraint waits on those before it in its group that
// share a dynamic body with it (the one-lane walk's order on each body, so the same bits); others
// may pass it. A slot's blocks are its lanes' most points, so each slot takes constraints of
// about as many points: of the blocks P it could have, the one that places the most rows a block
// (a slot's bodies cost about kSlotBlocks blocks more), the first ready in the split's order first
// (their bodies and points lie near in the caches).
void scheduleBundle(const GroupSpan* first, const GroupSpan* end, int lanes, const std::vector<LaneRecord>& records,
                    LaneSchedule& s, BundlePlan& plan) {
    constexpr double kSlotBlocks = 1.0;
    // The bundle's constraints in the split's order, and their waits on each body.
    s.place.clear();
    for (const GroupSpan* g = first; g != end; ++g)
        for (int k = g->offset; k < g->offset + g->count; ++k) s.place.push_back(k);
    const int n = int(s.place.size());
    s.waits.resize(std::size_t(n));
    using Waits = LaneSchedule::Waits;
    if (++s.number == 0) {  // the numbers wrapped: the marks of old schedules cleared
        std::fill(s.lastOn.begin(), s.lastOn.end(), std::pair<unsigned, int>{0u, -1});
        s.number = 1;
    }
    const unsigned bundle = s.number;
    int mostPoints = 0;
    for (int j = 0; j < n; ++j) {
        const LaneRecord& r = records[std::size_t(s.place[std::size_t(j)])];
        Waits& w = s.waits[std::size_t(j)];
        w = Waits{{-1, -1}, 0, r.points};
        mostPoints = std::max(mostPoints, r.points);
        for (int side = 0; side < 2; ++side) {
            const int body = side == 0 ? r.lockA : r.lockB;
            if (body < 0 || (side == 1 && body == r.lockA)) continue;
            if (std::size_t(body) >= s.lastOn.size()) s.lastOn.resize(std::size_t(body) + 1, {0u, -1});
            std::pair<unsigned, int>& last = s.lastOn[std::size_t(body)];
            if (last.first == bundle) {
                const LaneRecord& b = records[std::size_t(s.place[std::size_t(last.second)])];
                s.waits[std::size_t(last.second)].next[b.lockA == body ? 0 : 1] = j;
                ++w.waitsOn;
            }
            last = {bundle, j};
        }
    }
    const std::size_t words = (std::size_t(n) + 63) / 64;
    s.readyBits.resize(std::size_t(mostPoints) + 1);
    for (auto& bits : s.readyBits) bits.assign(words, 0);
    s.firstWord.assign(s.readyBits.size(), words);
    s.readyOf.assign(s.readyBits.size(), 0);
    const auto makeReady = [&](int j) {
        const std::size_t points = std::size_t(s.waits[std::size_t(j)].points), word = std::size_t(j) / 64;
        s.readyBits[points][word] |= std::uint64_t(1) << (j % 64);
        s.firstWord[points] = std::min(s.firstWord[points], word);
        ++s.readyOf[points];
    };
    // The first ready constraint of `points` in the split's order, taken.
    const auto take = [&](std::size_t points) {
        std::vector<std::uint64_t>& bits = s.readyBits[points];
        std::size_t& w = s.firstWord[points];
        while (bits[w] == 0) ++w;  // one is ready: readyOf says so
        const int j = int(w * 64 + std::size_t(__builtin_ctzll(bits[w])));
        bits[w] &= bits[w] - 1;
        --s.readyOf[points];
        s.taken.push_back(j);
    };
    for (int j = 0; j < n; ++j)
        if (s.waits[std::size_t(j)].waitsOn == 0) makeReady(j);

    plan.lanes.clear();
    plan.normalBlocks.clear();
    for (int left = n; left > 0;) {
        s.taken.clear();
        // The slot's blocks: the most rows a block, counting the slot's bodies.
        int bestPoints = 0, free = lanes, rows = 0;
        double bestScore = -1;
        for (int p = 0; p <= mostPoints; ++p) {
            const int count = std::min(free, s.readyOf[std::size_t(p)]);
            free -= count;
            rows += count * p;
            if (count == 0) continue;
            // Rows counted taking the fewest points first: at most what the slot places.
            const double score = rows / (p + kSlotBlocks);
            if (score > bestScore) {
                bestScore = score;
                bestPoints = p;
            }
        }
        for (int p = bestPoints; p >= 0 && int(s.taken.size()) < lanes; --p)
            while (s.readyOf[std::size_t(p)] > 0 && int(s.taken.size()) < lanes) take(std::size_t(p));
        if (s.taken.empty())  // the split's first constraint not taken is always ready
            throw btOpenCLSolverError("btOpenCLConstraintSolver: a lane schedule found no constraint ready");
        // The lanes in the order taken; what waited on them is ready from the next slot.
        int blocks = 0;
        s.freed.clear();
        for (int i = 0; i < lanes; ++i) {
            if (i >= int(s.taken.size())) {
                plan.lanes.push_back(-1);
                continue;
            }
            const int j = s.taken[std::size_t(i)];
            const Waits& w = s.waits[std::size_t(j)];
            blocks = std::max(blocks, w.points);
            plan.lanes.push_back(s.place[std::size_t(j)]);
            for (const int after : w.next)
                if (after >= 0 && --s.waits[std::size_t(after)].waitsOn == 0) s.freed.push_back(after);
        }
        for (const int j : s.freed) makeReady(j);
        plan.normalBlocks.push_back(blocks);
        left -= int(s.taken.size());
    }
}

// A scheduled bundle's slots written at its places: the slots, their lanes' ints and
// constraints, and its rows' places in the row map (rows lie in gather order, written here in
// solve order: each lane's row-map entries asked for a few slots ahead, as a group's first few
// wait on them). normalTotal: every bundle's normal blocks, before which no friction block lies.
// Returns the lanes and row places the bundle fills.
std::pair<long long, long long> writeBundle(const BundlePlan& plan, const std::vector<LaneRecord>& records,
                                            int normalTotal, LaneLayout& out) {
    const int W = out.lanes, perPoint = out.frictionPerPoint;
    const std::size_t numSlots = plan.normalBlocks.size();
    long long usedLanes = 0, usedRows = 0;
    int normalBlock = plan.firstNormalBlock;
    for (std::size_t t = 0; t < numSlots; ++t) {
        const std::size_t slotIndex = std::size_t(plan.firstSlot) + t;
        const int frictionBlock = normalTotal + normalBlock * perPoint;
        const int blocks = plan.normalBlocks[t];
        out.slots[slotIndex] = btoclLaneSlot{normalBlock, blocks, frictionBlock, blocks * perPoint};
        int* ints = out.laneInts.data() + slotIndex * BTOCL_LANE_INTS * std::size_t(W);
        std::fill(ints, ints + BTOCL_LANE_INTS * W, 0);
        for (int i = 0; i < W; ++i) {
            const std::size_t at = t * std::size_t(W) + std::size_t(i);
            const int k = plan.lanes[at];
            if (k < 0) {
                out.laneConstraint[slotIndex * std::size_t(W) + std::size_t(i)] = -1;
                continue;
            }
            if (at + kPrefetchAhead * std::size_t(W) < plan.lanes.size()) {
                const int ahead = plan.lanes[at + kPrefetchAhead * std::size_t(W)];
                if (ahead >= 0) {
                    prefetch(out.rowMap.data() + records[std::size_t(ahead)].firstNormal);
                    prefetch(out.rowMap.data() + records[std::size_t(ahead)].firstFriction);
                }
            }
            const LaneRecord& c = records[std::size_t(k)];
            ints[BTOCL_LANE_BODY_A * W + i] = c.bodyA;
            ints[BTOCL_LANE_BODY_B * W + i] = c.bodyB;
            ints[BTOCL_LANE_POINTS * W + i] = c.points;
            ints[BTOCL_LANE_FIRST_POINT * W + i] = c.firstNormal;
            out.laneConstraint[slotIndex * std::size_t(W) + std::size_t(i)] = c.constraint;
            for (int r = 0; r < c.points; ++r)
                out.rowMap[std::size_t(c.firstNormal + r)] = (normalBlock + r) * W + i;
            for (int r = 0; r < c.points * perPoint; ++r)
                out.rowMap[std::size_t(c.firstFriction + r)] = (frictionBlock + r) * W + i;
            usedLanes += 1;
            usedRows += c.points * (1 + perPoint);
        }
        normalBlock += blocks;
    }
    return {usedLanes, usedRows};
}

// A set's groups (from firstGroup on) to the bundles of their cells' runs: the set's cells cut by
// their points (a bundle's blocks; cutCells). Each bundle holds one region of the scene in every
// set, and a body, whose constraints lie in neighbouring cells, mostly stays in one bundle's place
// from set to set: on the host's threads (HostLaneSolve), each bundle place a thread's, in its
// core's cache (docs/performance.md, "Lanes on the host's threads"). Cut in each set, by points,
// its bundles end together: each set's last waits on the others (docs/performance.md, "Bundles
// cut by their set's points").
void dealByPlace(const BatchLayout& split, int firstGroup, const std::vector<LaneRecord>& records, int parts,
                 std::vector<std::pair<int, long long>>& cells, std::vector<int>& bundleOf) {
    cells.clear();
    for (std::size_t k = 0; k < bundleOf.size(); ++k) {
        const btoclGroup& g = split.groups[std::size_t(firstGroup) + k];
        long long points = 0;
        for (int i = g.offset; i < g.offset + g.count; ++i) points += records[std::size_t(i)].points;
        cells.emplace_back(g.cell, points);
    }
    const std::vector<int> cuts = cutCells(cells, parts);
    for (std::size_t k = 0; k < bundleOf.size(); ++k) bundleOf[k] = partOfCell(cuts, cells[k].first);
}

// The groups of a set share no dynamic body, so any bundle may take any of them: the largest
// first, each to the bundle with the fewest constraints so far (the lowest where they tie), so
// that the bundles end together. For the overflow set, whose group has no cell, and a set of too
// few groups for a bundle a thread.
void dealBySize(const BatchLayout& split, int firstGroup, int numBundles, std::vector<int>& order,
                std::vector<std::pair<long long, int>>& shortest, std::vector<int>& bundleOf) {
    const int numGroups = int(bundleOf.size());
    order.resize(std::size_t(numGroups));
    for (int k = 0; k < numGroups; ++k) order[std::size_t(k)] = firstGroup + k;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return split.groups[std::size_t(a)].count > split.groups[std::size_t(b)].count;
    });
    shortest.clear();  // a min-heap of (constraints, bundle)
    for (int b = 0; b < numBundles; ++b) shortest.emplace_back(0, b);
    for (const int g : order) {
        std::pop_heap(shortest.begin(), shortest.end(), std::greater<>());
        std::pair<long long, int>& bundle = shortest.back();
        bundle.first += split.groups[std::size_t(g)].count;
        bundleOf[std::size_t(g - firstGroup)] = bundle.second;
        std::push_heap(shortest.begin(), shortest.end(), std::greater<>());
    }
}

}  // namespace

void layOutLanes(const BatchLayout& split, const btoclConstraint* constraints, const btoclRowRegions& regions,
                 int lanes, int frictionPerPoint, int bundlesPerSet, LaneLayout& out) {
    if (lanes < 2 || frictionPerPoint < 1 || !split.serialRuns)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a lane layout needs 2 lanes or more and a serial split");
    out.lanes = lanes;
    out.frictionPerPoint = frictionPerPoint;
    std::vector<LaneRecord>& records = out.records;
    readLaneRecords(split, constraints, frictionPerPoint, records);

    // Each set's groups dealt to its bundles, serially (a sort and a heap a set).
    std::vector<int> order, bundleOf, bundleFirst;
    std::vector<std::pair<long long, int>> shortest;
    std::vector<std::pair<int, long long>> setCells;
    std::vector<GroupSpan> spans;
    std::vector<BundlePlan> plans;
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        out.setBundleStart[std::size_t(set)] = int(plans.size());
        const int firstGroup = split.setGroupStart[std::size_t(set)];
        const int groupEnd = split.setGroupStart[std::size_t(set) + 1];
        const int numGroups = groupEnd - firstGroup;
        if (numGroups == 0) continue;
        const int mostBundles = (numGroups + lanes - 1) / lanes;  // one group a lane at least
        // A bundle a unit: the fewer the bundles, the more groups each slot chooses among, and the
        // fuller its lanes (docs/performance.md, "A bundle a unit").
        const int numBundles = std::max(1, std::min(mostBundles, bundlesPerSet));
        bundleOf.assign(std::size_t(numGroups), 0);
        if (set < BTOCL_OVERFLOW_SET && numBundles == bundlesPerSet)
            dealByPlace(split, firstGroup, records, numBundles, setCells, bundleOf);
        else
            dealBySize(split, firstGroup, numBundles, order, shortest, bundleOf);
        // Each bundle's groups in the split's order (a counting sort by bundle).
        const int base = int(spans.size());
        bundleFirst.assign(std::size_t(numBundles) + 1, 0);
        for (int k = 0; k < numGroups; ++k) ++bundleFirst[std::size_t(bundleOf[std::size_t(k)]) + 1];
        for (int b = 0; b < numBundles; ++b) bundleFirst[std::size_t(b) + 1] += bundleFirst[std::size_t(b)];
        spans.resize(std::size_t(base + numGroups));
        std::vector<int> fill(bundleFirst.begin(), bundleFirst.end() - 1);
        for (int k = 0; k < numGroups; ++k) {
            const btoclGroup& g = split.groups[std::size_t(firstGroup + k)];
            spans[std::size_t(base + fill[std::size_t(bundleOf[std::size_t(k)])]++)] = GroupSpan{g.offset, g.count};
        }
        for (int b = 0; b < numBundles; ++b) {
            plans.emplace_back();
            plans.back().firstGroup = base + bundleFirst[std::size_t(b)];
            plans.back().endGroup = base + bundleFirst[std::size_t(b) + 1];
        }
    }
    out.setBundleStart[BTOCL_NUM_SETS + 1] = int(plans.size());

    // Every bundle scheduled apart (its groups are its own), then placed after the ones before.
    const std::size_t bundleWeight = kManifoldWeight * (records.size() / std::max<std::size_t>(1, plans.size()) + 1);
    if (out.schedules.size() < plans.size()) out.schedules.resize(plans.size());
    parallelFor(plans.size(), [&](std::size_t b) {
        scheduleBundle(spans.data() + plans[b].firstGroup, spans.data() + plans[b].endGroup, lanes, records,
                       out.schedules[b], plans[b]);
    }, bundleWeight);
    int numSlots = 0, normalTotal = 0;
    out.bundles.resize(plans.size());
    for (std::size_t b = 0; b < plans.size(); ++b) {
        const int slots = int(plans[b].normalBlocks.size());
        out.bundles[b] = btoclGroup{numSlots, slots, 1, -1};
        plans[b].firstSlot = numSlots;
        plans[b].firstNormalBlock = normalTotal;
        numSlots += slots;
        for (const int blocks : plans[b].normalBlocks) normalTotal += blocks;
    }
    resizeForOverwrite(out.slots, std::size_t(numSlots));
    resizeForOverwrite(out.laneInts, std::size_t(numSlots) * BTOCL_LANE_INTS * std::size_t(lanes));
    resizeForOverwrite(out.laneConstraint, std::size_t(numSlots) * std::size_t(lanes));
    // Every row is some constraint's, and each constraint is written once: no entry stays unset.
    resizeForOverwrite(out.rowMap, std::size_t(regions.start[BTOCL_NUM_ROW_KINDS]));
    std::vector<std::pair<long long, long long>> used(plans.size());
    parallelFor(plans.size(), [&](std::size_t b) { used[b] = writeBundle(plans[b], records, normalTotal, out); },
                bundleWeight);
    out.usedLanes = 0;
    out.usedRowPlaces = 0;
    for (const auto& u : used) {
        out.usedLanes += u.first;
        out.usedRowPlaces += u.second;
    }
    out.numBlocks = normalTotal * (1 + frictionPerPoint);
}

std::string validateLaneLayout(const LaneLayout& l, const BatchLayout& split,
                               const std::vector<btoclConstraint>& constraints) {
    const int W = l.lanes;
    if (W < 2) return "fewer than 2 lanes";
    const std::size_t numSlots = l.slots.size();
    if (l.laneInts.size() != numSlots * BTOCL_LANE_INTS * std::size_t(W) || l.laneConstraint.size() != numSlots * std::size_t(W))
        return "a slot's lanes are not W";
    // Where each constraint lies in the split: its set and group.
    std::vector<int> setOf(constraints.size(), -1), groupOf(constraints.size(), -1);
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set)
        for (int g = split.setGroupStart[std::size_t(set)]; g < split.setGroupStart[std::size_t(set) + 1]; ++g)
            for (int k = 0; k < split.groups[std::size_t(g)].count; ++k) {
                const std::size_t ci = std::size_t(split.solveOrder[std::size_t(split.groups[std::size_t(g)].offset + k)]);
                setOf[ci] = set;
                groupOf[ci] = g;
            }
    // A group's constraints on each of its dynamic bodies in its order, slot after slot: the
    // one-lane walk's order on every body.
    std::vector<int> slotOf(constraints.size(), -1), lastSlotOn;
    for (std::size_t at = 0; at < l.laneConstraint.size(); ++at) {
        const int ci = l.laneConstraint[at];
        if (ci >= 0 && std::size_t(ci) < constraints.size()) slotOf[std::size_t(ci)] = int(at / std::size_t(W));
    }
    for (const btoclGroup& g : split.groups) {
        for (int k = 0; k < g.count; ++k) {
            const std::size_t ci = std::size_t(split.solveOrder[std::size_t(g.offset + k)]);
            for (int side = 0; side < 2; ++side) {
                const int body = dynamicBodyOf(constraints[ci], side);
                if (body < 0 || slotOf[ci] < 0 || (side == 1 && body == dynamicBodyOf(constraints[ci], 0))) continue;
                if (std::size_t(body) >= lastSlotOn.size()) lastSlotOn.resize(std::size_t(body) + 1, -1);
                if (slotOf[ci] <= lastSlotOn[std::size_t(body)]) return "a body's constraints out of their group's order";
                lastSlotOn[std::size_t(body)] = slotOf[ci];
            }
        }
        for (int k = 0; k < g.count; ++k) {
            const std::size_t ci = std::size_t(split.solveOrder[std::size_t(g.offset + k)]);
            for (int side = 0; side < 2; ++side)
                if (dynamicBodyOf(constraints[ci], side) >= 0) lastSlotOn[std::size_t(dynamicBodyOf(constraints[ci], side))] = -1;
        }
    }
    std::vector<int> seen(constraints.size(), 0);
    std::vector<int> rowOwner(std::size_t(l.numBlocks) * std::size_t(W), -1);
    std::vector<int> bodies;
    // Per group: its bundle.
    const std::size_t numGroups = split.groups.size();
    std::vector<int> bundleOfGroup(numGroups, -1);
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        for (int bi = l.setBundleStart[std::size_t(set)]; bi < l.setBundleStart[std::size_t(set) + 1]; ++bi) {
            const btoclGroup& bundle = l.bundles[std::size_t(bi)];
            if (bundle.offset < 0 || bundle.offset + bundle.count > int(numSlots)) return "a bundle past the slots";
            for (int t = 0; t < bundle.count; ++t) {
                const std::size_t slot = std::size_t(bundle.offset + t);
                const int* ints = l.laneInts.data() + slot * BTOCL_LANE_INTS * std::size_t(W);
                for (int i = 0; i < W; ++i) {
                    const int ci = l.laneConstraint[slot * std::size_t(W) + std::size_t(i)];
                    if (ci < 0) {
                        if (ints[BTOCL_LANE_POINTS * W + i] != 0) return "an unused lane holds rows";
                        continue;
                    }
                    const btoclConstraint& c = constraints[std::size_t(ci)];
                    seen[std::size_t(ci)] += 1;
                    if (setOf[std::size_t(ci)] != set) return "a lane holds a constraint of another set";
                    const std::size_t g = std::size_t(groupOf[std::size_t(ci)]);
                    if (bundleOfGroup[g] < 0) bundleOfGroup[g] = bi;
                    if (bundleOfGroup[g] != bi) return "a group in two bundles";
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
    for (std::size_t c = 0; c < seen.size(); ++c)  // the split's, once; others (a step's joints), never
        if (seen[c] != (setOf[c] >= 0 ? 1 : 0)) return "a constraint is not in exactly one lane";
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
