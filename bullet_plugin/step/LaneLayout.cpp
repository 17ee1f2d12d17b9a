#include "LaneLayout.h"

#include "HostParallel.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cstddef>
#include <functional>
#include <utility>

namespace btocl {
namespace {

// A bundle takes about this many groups a lane where a set has enough: its slots have heads of
// several groups to choose from, and fewer bundles leave fewer lanes empty.
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

namespace {

// A group of a bundle as the slots take it: its first place in the solve order, its next
// constraint's position in it.
struct GroupCursor {
    int offset, position, count;
    int remaining() const { return count - position; }
};

// What a slot reads of a constraint, by solve order.
struct LaneRecord {
    int constraint, bodyA, bodyB, points, firstNormal, firstFriction;
};

// Writes the slots of the layout.
class SlotWriter {
public:
    // The constraints' records by solve order, read ahead of the slots on the host's threads: a
    // loop of independent loads waits on the scattered records far less than the slots, whose
    // choices wait on each. Throws btOpenCLSolverError for a constraint the lanes do not solve.
    SlotWriter(const BatchLayout& split, const btoclConstraint* constraints, int frictionPerPoint, LaneLayout& out)
        : m_perPoint(frictionPerPoint), m_out(out) {
        m_records.resize(split.solveOrder.size());
        parallelFor(m_records.size(), [&](std::size_t k) {
            const int ci = split.solveOrder[k];
            const btoclConstraint& c = constraints[ci];
            const int points = c.numRows[BTOCL_ROWS_NORMAL];
            if (c.numRows[BTOCL_ROWS_FRICTION] != frictionPerPoint * points || c.numRows[BTOCL_ROWS_ROLLING] != 0 ||
                c.numRows[BTOCL_ROWS_JOINT] != 0)
                throw btOpenCLSolverError(
                    "btOpenCLConstraintSolver: a constraint with rows the lanes do not solve was laid out in lanes");
            m_records[k] = LaneRecord{ci, c.bodyA, c.bodyB, points, c.firstRow[BTOCL_ROWS_NORMAL],
                                      c.firstRow[BTOCL_ROWS_FRICTION]};
        }, kManifoldWeight);
    }

    int pointsOf(const GroupCursor& g) const { return recordOf(g, g.position).points; }

    // One slot of the lanes' groups' next constraints, in lane order; each group moves on.
    void write(GroupCursor* const* lanes, int taken) {
        const std::size_t W = std::size_t(m_out.lanes);
        btoclLaneSlot slot{m_normalBlocks, 0, m_frictionBlocks, 0};
        const std::size_t ints = m_out.laneInts.size();
        m_out.laneInts.resize(ints + BTOCL_LANE_INTS * W, 0);
        for (std::size_t i = 0; i < W; ++i) {
            if (int(i) >= taken) {
                m_out.laneConstraint.push_back(-1);
                continue;
            }
            GroupCursor& g = *lanes[i];
            // Rows lie in gather order, placed here in solve order: the row map's entries of the
            // group's constraint a few slots ahead asked for (a group's first few wait), and
            // its record twice as far ahead.
            if (g.position + 2 * kPrefetchAhead < g.count) prefetch(&recordOf(g, g.position + 2 * kPrefetchAhead));
            if (g.position + kPrefetchAhead < g.count) {
                const LaneRecord& ahead = recordOf(g, g.position + kPrefetchAhead);
                prefetch(m_out.rowMap.data() + ahead.firstNormal);
                prefetch(m_out.rowMap.data() + ahead.firstFriction);
            }
            const LaneRecord& c = recordOf(g, g.position++);
            m_out.laneInts[ints + BTOCL_LANE_BODY_A * W + i] = c.bodyA;
            m_out.laneInts[ints + BTOCL_LANE_BODY_B * W + i] = c.bodyB;
            m_out.laneInts[ints + BTOCL_LANE_POINTS * W + i] = c.points;
            m_out.laneInts[ints + BTOCL_LANE_FIRST_POINT * W + i] = c.firstNormal;
            m_out.laneConstraint.push_back(c.constraint);
            const int lanesW = m_out.lanes, lane = int(i);
            for (int k = 0; k < c.points; ++k)
                m_out.rowMap[std::size_t(c.firstNormal + k)] = (m_normalBlocks + k) * lanesW + lane;
            for (int k = 0; k < c.points * m_perPoint; ++k)
                m_out.rowMap[std::size_t(c.firstFriction + k)] = (m_frictionBlocks + k) * lanesW + lane;
            slot.normalBlocks = std::max(slot.normalBlocks, c.points);
            m_out.usedLanes += 1;
            m_out.usedRowPlaces += c.points * (1 + m_perPoint);
        }
        slot.frictionBlocks = slot.normalBlocks * m_perPoint;
        m_normalBlocks += slot.normalBlocks;
        m_frictionBlocks += slot.frictionBlocks;
        m_out.slots.push_back(slot);
    }

    int normalBlocks() const { return m_normalBlocks; }
    int frictionBlocks() const { return m_frictionBlocks; }

private:
    const LaneRecord& recordOf(const GroupCursor& g, int position) const {
        return m_records[std::size_t(g.offset + position)];
    }

    int m_perPoint;
    LaneLayout& m_out;
    std::vector<LaneRecord> m_records;
    int m_normalBlocks = 0, m_frictionBlocks = 0;  // friction blocks counted from the friction region's start
};

// A bundle's slots from its groups [first, end) (in the split's order). A slot's blocks are its lanes' most
// points, so each slot takes the groups whose next constraints have about as many points: of
// the blocks P it could have, the one that places the most rows a block (a slot's bodies cost
// about kSlotBlocks blocks more). A group that has as many constraints left as the bundle has
// slots left to its length (its total over W, or its longest group) goes first, so the bundle
// ends near that length.
void scheduleBundle(GroupCursor* first, GroupCursor* end, int lanes, SlotWriter& writer,
                    std::vector<GroupCursor*>& active, std::vector<std::vector<GroupCursor*>>& byPoints,
                    std::vector<GroupCursor*>& taken) {
    constexpr double kSlotBlocks = 1.0;
    long long total = 0;
    int longest = 0;
    active.clear();
    for (GroupCursor* g = first; g != end; ++g) {
        total += g->count;
        longest = std::max(longest, g->count);
        if (g->count > 0) active.push_back(g);
    }
    const long long length = std::max<long long>(longest, (total + lanes - 1) / lanes);
    for (long long slot = 0; !active.empty(); ++slot) {
        const long long slotsLeft = std::max<long long>(1, length - slot);
        taken.clear();
        for (auto& list : byPoints) list.clear();
        int firstPoints = 0, takenRows = 0;
        for (GroupCursor* g : active) {
            const int points = writer.pointsOf(*g);
            if (g->remaining() >= slotsLeft && int(taken.size()) < lanes) {
                taken.push_back(g);
                firstPoints = std::max(firstPoints, points);
                takenRows += points;
            } else {
                if (std::size_t(points) >= byPoints.size()) byPoints.resize(std::size_t(points) + 1);
                byPoints[std::size_t(points)].push_back(g);
            }
        }
        // The slot's blocks: the most rows a block, counting the slot's bodies.
        if (std::size_t(firstPoints) >= byPoints.size()) byPoints.resize(std::size_t(firstPoints) + 1);
        int bestPoints = firstPoints;
        if (int(taken.size()) < lanes) {
            double bestScore = -1;
            int free = lanes - int(taken.size()), rows = takenRows;
            for (int p = 0; p < int(byPoints.size()); ++p) {
                const int take = std::min(free, int(byPoints[std::size_t(p)].size()));
                free -= take;
                rows += take * p;
                if (p < firstPoints || (take == 0 && p > firstPoints)) continue;
                // Rows counted taking the fewest points first: at most what the slot places.
                const double score = rows / (p + kSlotBlocks);
                if (score > bestScore) {
                    bestScore = score;
                    bestPoints = p;
                }
            }
            for (int p = bestPoints; p >= 0 && int(taken.size()) < lanes; --p)
                for (GroupCursor* g : byPoints[std::size_t(p)]) {
                    if (int(taken.size()) >= lanes) break;
                    taken.push_back(g);
                }
        }
        writer.write(taken.data(), int(taken.size()));
        active.erase(std::remove_if(active.begin(), active.end(), [](const GroupCursor* g) { return g->remaining() == 0; }),
                     active.end());
    }
}

}  // namespace

void layOutLanes(const BatchLayout& split, const btoclConstraint* constraints, const btoclRowRegions& regions,
                 int lanes, int frictionPerPoint, int minBundlesPerSet, LaneLayout& out) {
    if (lanes < 2 || frictionPerPoint < 1 || !split.serialRuns)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a lane layout needs 2 lanes or more and a serial split");
    out.lanes = lanes;
    out.frictionPerPoint = frictionPerPoint;
    out.bundles.clear();
    out.slots.clear();
    out.laneInts.clear();
    out.laneConstraint.clear();
    out.rowMap.assign(std::size_t(regions.start[BTOCL_NUM_ROW_KINDS]), -1);
    out.usedLanes = 0;
    out.usedRowPlaces = 0;
    SlotWriter writer(split, constraints, frictionPerPoint, out);
    std::vector<int> order, bundleOf, bundleFirst;
    std::vector<std::pair<long long, int>> shortest;
    std::vector<GroupCursor> cursors;
    std::vector<std::vector<GroupCursor*>> byPoints;  // by their next constraint's points
    std::vector<GroupCursor*> active, taken;
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        out.setBundleStart[std::size_t(set)] = int(out.bundles.size());
        const int firstGroup = split.setGroupStart[std::size_t(set)];
        const int groupEnd = split.setGroupStart[std::size_t(set) + 1];
        const int numGroups = groupEnd - firstGroup;
        if (numGroups == 0) continue;
        const int mostBundles = (numGroups + lanes - 1) / lanes;  // one group a lane at least
        const int numBundles =
            std::max(1, std::min(mostBundles, std::max(minBundlesPerSet, numGroups / (kGroupsPerLane * lanes))));
        // The groups of a set share no dynamic body, so any bundle may take any of them: the
        // largest first, each to the bundle with the fewest constraints so far (the lowest where
        // they tie), so that the bundles end together.
        order.resize(std::size_t(numGroups));
        for (int k = 0; k < numGroups; ++k) order[std::size_t(k)] = firstGroup + k;
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
            return split.groups[std::size_t(a)].count > split.groups[std::size_t(b)].count;
        });
        bundleOf.assign(std::size_t(numGroups), 0);
        shortest.clear();  // a min-heap of (constraints, bundle)
        for (int b = 0; b < numBundles; ++b) shortest.emplace_back(0, b);
        for (const int g : order) {
            std::pop_heap(shortest.begin(), shortest.end(), std::greater<>());
            std::pair<long long, int>& bundle = shortest.back();
            bundle.first += split.groups[std::size_t(g)].count;
            bundleOf[std::size_t(g - firstGroup)] = bundle.second;
            std::push_heap(shortest.begin(), shortest.end(), std::greater<>());
        }
        // Each bundle's groups in the split's order (a counting sort by bundle).
        bundleFirst.assign(std::size_t(numBundles) + 1, 0);
        for (int k = 0; k < numGroups; ++k) ++bundleFirst[std::size_t(bundleOf[std::size_t(k)]) + 1];
        for (int b = 0; b < numBundles; ++b) bundleFirst[std::size_t(b) + 1] += bundleFirst[std::size_t(b)];
        cursors.resize(std::size_t(numGroups));
        {
            std::vector<int> fill(bundleFirst.begin(), bundleFirst.end() - 1);
            for (int k = 0; k < numGroups; ++k)
                cursors[std::size_t(fill[std::size_t(bundleOf[std::size_t(k)])]++)] =
                    GroupCursor{split.groups[std::size_t(firstGroup + k)].offset, 0,
                                split.groups[std::size_t(firstGroup + k)].count};
        }
        for (int b = 0; b < numBundles; ++b) {
            const int firstSlot = int(out.slots.size());
            scheduleBundle(cursors.data() + bundleFirst[std::size_t(b)], cursors.data() + bundleFirst[std::size_t(b) + 1],
                           lanes, writer, active, byPoints, taken);
            out.bundles.push_back(btoclGroup{firstSlot, int(out.slots.size()) - firstSlot, 1, -1});
        }
    }
    out.setBundleStart[BTOCL_NUM_SETS + 1] = int(out.bundles.size());
    const int normalBlocks = writer.normalBlocks();
    // The friction region after every normal block.
    for (btoclLaneSlot& slot : out.slots) slot.frictionBlock += normalBlocks;
    const int frictionShift = normalBlocks * lanes;
    for (int r = regions.start[BTOCL_ROWS_FRICTION]; r < regions.start[BTOCL_ROWS_ROLLING]; ++r) {
        out.rowMap[std::size_t(r)] += frictionShift;
    }
    out.numBlocks = normalBlocks + writer.frictionBlocks();
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
    // Per group: its bundle, the slot of its constraint last seen, the position of its next.
    const std::size_t numGroups = split.groups.size();
    std::vector<int> bundleOfGroup(numGroups, -1), lastSlotOfGroup(numGroups, -1), nextPosition(numGroups, 0);
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
                    if (lastSlotOfGroup[g] == int(slot)) return "a group twice in a slot";
                    if (positionOf[std::size_t(ci)] != nextPosition[g]) return "a group's constraints out of its order";
                    lastSlotOfGroup[g] = int(slot);
                    nextPosition[g] += 1;
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
