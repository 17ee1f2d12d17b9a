// A split step laid out for its groups to be solved in lanes (a CPU's vector unit; kernels/
// lane_solve.h, docs/architecture.md "Lanes"). Groups of one set share no dynamic body, so each
// set's groups are dealt to B bundles of W lanes: by place where a set has groups for all B
// (bundle b of every set takes the cells of the b-th of B runs of the scene's cells in row
// order, so that a body stays in one bundle's place from set to set), else by size (the largest
// group first, to the bundle with the fewest constraints); and each slot of a bundle takes the
// next constraints of up to W of its groups, one a group, chosen so that the slot's lanes have
// about as many points (a slot's blocks are its most points). A group's constraints go in its
// order, so each constraint meets its bodies as in the one-lane walk: the same bits.
#pragma once

#include "BatchLayout.h"
#include "HostArray.h"
#include "btocl_shared.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace btocl {

// A bundle's schedule's working arrays (layOutLanes), kept from step to step in its layout.
struct LaneSchedule {
    // A constraint of the bundle as the schedule sees it: the constraints after it in its group
    // that wait on it (the next on each of its dynamic bodies), how many before it it waits on,
    // its points.
    struct Waits {
        int next[2];
        int waitsOn, points;
    };
    // Per body: the last schedule that met it (its number) and its last constraint there, so that
    // no pass clears it between steps.
    std::vector<std::pair<unsigned, int>> lastOn;
    unsigned number = 0;
    std::vector<Waits> waits;
    std::vector<int> place;  // per bundle constraint: its place in the solve order
    // Ready constraints by their points: a bit each by its place in the split's order, the first
    // word that may hold one, how many there are.
    std::vector<std::vector<std::uint64_t>> readyBits;
    std::vector<std::size_t> firstWord;
    std::vector<int> readyOf;
    std::vector<int> taken, freed;
};

// What a slot reads of a constraint, by solve order; lockA and lockB: its dynamic bodies (-1
// where a side's body is not dynamic).
struct LaneRecord {
    int constraint, bodyA, bodyB, points, firstNormal, firstFriction, lockA, lockB;
};

struct LaneLayout {
    int lanes = 0;                    // W
    int frictionPerPoint = 1;
    std::vector<btoclGroup> bundles;  // per bundle: offset = its first slot, count = its slots
    std::array<int, BTOCL_NUM_SETS + 2> setBundleStart{};  // bundles of set s: [start[s], start[s + 1])
    std::vector<btoclLaneSlot> slots;
    std::vector<int> laneInts;        // per slot, BTOCL_LANE_INTS * W ints (btocl_shared.h)
    std::vector<int> laneConstraint;  // per slot and lane (s * W + i): its constraint, or -1
    std::vector<int> rowMap;          // per row in gather order: its wide row index (block * W + lane)
    int numBlocks = 0;                // blocks of W rows, normal ones first
    long long usedLanes = 0;          // slots' lanes that hold a constraint
    long long usedRowPlaces = 0;      // rows placed, of numBlocks * W places
    std::vector<LaneSchedule> schedules;  // per bundle: its schedule's arrays
    std::vector<LaneRecord> records;      // per place in the solve order: its constraint's (layOutLanes)

    double laneFill() const { return slots.empty() ? 0 : double(usedLanes) / (double(slots.size()) * lanes); }
    double rowFill() const { return numBlocks == 0 ? 0 : double(usedRowPlaces) / (double(numBlocks) * lanes); }
};

// What the setup of a lane layout's contact rows writes (setup.cl's setupLaneSlots, or the
// host's setUpLaneRows): the rows' blocks, their impulses by wide row; and the bodies' per-unit
// scales (lane_solve.h), set by the host for either. Host arrays, so that a device in the host's
// memory reads them in place.
struct LaneRows {
    HostArray<float> rows;                  // blocks of W rows (btoclWideRowFloat)
    HostArray<float> applied, pushApplied;  // by wide row
    HostArray<float> perUnit;               // per body, BTOCL_BODY_PER_UNIT_FLOATS (setUpBodyPerUnit)
    std::vector<unsigned char> inVectors;   // per slot: its rows set up eight points at a time
};

// Whether a step's rows can be solved in lanes: contact rows alone (no joint or rolling rows),
// each point with `frictionPerPoint` friction rows.
bool rowsFitLanes(const btoclRowRegions& regions, int frictionPerPoint);
// The same but for joint rows, which the contacts' lanes leave to lanes of their own (HostLaneSolve).
bool contactRowsFitLanes(const btoclRowRegions& regions, int frictionPerPoint);

// `split` (the serial path's: one run a group) laid out in `lanes` lanes into `out`, its arrays
// reused, with `bundlesPerSet` bundles a set where it has groups enough for their lanes (one per
// compute unit, which claim them; one per host thread, which share them out). Every constraint
// must have numRows[FRICTION] == frictionPerPoint * numRows[NORMAL] and no other rows
// (rowsFitLanes); throws btOpenCLSolverError otherwise.
void layOutLanes(const BatchLayout& split, const btoclConstraint* constraints, const btoclRowRegions& regions,
                 int lanes, int frictionPerPoint, int bundlesPerSet, LaneLayout& out);

// The lane layout's invariants against its split: every constraint of the split in one lane of
// one slot (and no other constraint in any), each group in one bundle of its set, the
// constraints on each dynamic body in their group's order from slot to slot, no dynamic body
// twice in a slot, every row placed once in its lane and its slot's blocks, each lane's ints
// those of its constraint. Returns "" or the first failure.
std::string validateLaneLayout(const LaneLayout& lanes, const BatchLayout& split,
                               const std::vector<btoclConstraint>& constraints);

}  // namespace btocl
