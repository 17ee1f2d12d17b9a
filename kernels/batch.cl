// Local batch creation (docs/architecture.md, "Local batches"; the paper's §2.2): one work-group
// per constraint group splits the group into batches in which no dynamic body appears twice.
//
// The group streams through a local window of BTOCL_BATCH_WINDOW constraints. The window's dynamic bodies
// have exact slots in a local open-addressing table (so no false conflicts). For each batch `rounds`
// locking rounds run: every pending constraint offers its priority (batch_priority.h: a hash of its
// index, then its window position) to the slots of its bodies with atomic_min; a constraint that holds
// the minimum of all its slots is scheduled and locks them; one whose body is locked waits for the
// next batch. Only minima decide, so the result does not depend on the order lanes run in, and the
// smallest pending priority always wins: each batch takes at least one constraint. Scheduled
// constraints leave through a local output buffer at positions from a prefix sum over lanes; the rest
// are compacted (in order) and the window is refilled from the group. No lane ever waits for another
// except at barriers, which every lane reaches (uniform loops).
#include "btocl_shared.h"
#include "batch_priority.h"

#ifndef BTOCL_BATCH_WG
#define BTOCL_BATCH_WG 64
#endif
#ifndef BTOCL_BATCH_WINDOW
#define BTOCL_BATCH_WINDOW 512  // a multiple of BTOCL_BATCH_WG
#endif
#ifndef BTOCL_BATCH_TABLE_BITS
#define BTOCL_BATCH_TABLE_BITS 11  // 2^bits >= 4 * BTOCL_BATCH_WINDOW slots
#endif
#ifndef BTOCL_BATCH_WINDOW_BITS
#define BTOCL_BATCH_WINDOW_BITS 9  // BTOCL_BATCH_WINDOW <= 2^bits
#endif
#define BTOCL_BATCH_TABLE (1 << BTOCL_BATCH_TABLE_BITS)
#define BTOCL_BATCH_PER_LANE (BTOCL_BATCH_WINDOW / BTOCL_BATCH_WG)

#define BTOCL_EMPTY_BODY (-1)
#define BTOCL_NO_OFFER 0x7fffffff
#define BTOCL_BATCH_PENDING 0
#define BTOCL_BATCH_BLOCKED 1
#define BTOCL_BATCH_SCHEDULED 2

// The slot of `body` in a table of 2^bits slots, inserting it if new. Lock-free: a slot goes from
// empty to a body once, so every lane probing for the same body walks the same filled slots and stops
// at the same one. The table is never more than half full, so the probe ends.
static int batchTableSlot(__local int* keys, int bits, int body) {
    const int mask = (1 << bits) - 1;
    uint h = ((uint)body * 2654435761u) >> (32 - bits);
    for (int probe = 0; probe <= mask; ++probe) {
        const int old = atomic_cmpxchg(&keys[h], BTOCL_EMPTY_BODY, body);
        if (old == BTOCL_EMPTY_BODY || old == body) return (int)h;
        h = (h + 1) & mask;
    }
    return 0;  // unreachable (see above)
}

__kernel __attribute__((reqd_work_group_size(BTOCL_BATCH_WG, 1, 1)))
void batchGroups(__global const btoclConstraint* constraints, __global const int* sorted,
                 __global btoclGroup* groups, int rounds, __global int* solveOrder, __global int* batchEnd) {
    __local int winIdx[2][BTOCL_BATCH_WINDOW];  // ping-pong window: constraint index
    __local int winA[2][BTOCL_BATCH_WINDOW];    // its dynamic bodies, or -1
    __local int winB[2][BTOCL_BATCH_WINDOW];
    __local int winSlotA[2][BTOCL_BATCH_WINDOW];  // their table slots, or -1
    __local int winSlotB[2][BTOCL_BATCH_WINDOW];
    __local int state[BTOCL_BATCH_WINDOW];
    __local int prio[BTOCL_BATCH_WINDOW];
    __local int owns[BTOCL_BATCH_WINDOW];  // bit 0/1: this entry's offer is the minimum of slot A/B
    __local int outBuf[BTOCL_BATCH_WINDOW];
    __local int tableKey[BTOCL_BATCH_TABLE], tableBest[BTOCL_BATCH_TABLE], tableLocked[BTOCL_BATCH_TABLE];
    __local int laneScheduled[BTOCL_BATCH_WG], laneRest[BTOCL_BATCH_WG];
    __local int totals[2];
    __local int stillPending[2];  // by round parity: some constraint is pending after the decision

    const int lid = get_local_id(0);
    const int gid = get_group_id(0);
    const int offset = groups[gid].offset, count = groups[gid].count;
    const int myBegin = lid * BTOCL_BATCH_PER_LANE;
    int cur = 0, winSize = 0, next = 0, emitted = 0, batch = 0;
    // The body table: sized for the group (small groups clear small tables) and kept from batch to
    // batch; rebuilt only when the bodies inserted since the last build could pass half of it.
    int tableBits = 3;
    while ((1 << tableBits) < 4 * min(count, BTOCL_BATCH_WINDOW)) ++tableBits;
    const int tableSize = 1 << tableBits;
    int tableUsed = 0;

    for (;;) {
        // Refill the window's tail from the group, in order.
        const int add = min(BTOCL_BATCH_WINDOW - winSize, count - next);
        for (int k = lid; k < add; k += BTOCL_BATCH_WG) {
            const int ci = sorted[offset + next + k];
            winIdx[cur][winSize + k] = ci;
            winA[cur][winSize + k] = constraints[ci].dynamicA ? constraints[ci].bodyA : -1;
            winB[cur][winSize + k] = constraints[ci].dynamicB ? constraints[ci].bodyB : -1;
        }
        winSize += add;
        next += add;
        if (winSize == 0) break;  // uniform: every lane holds the same counters

        const bool rebuild = batch == 0 || tableUsed + 2 * add > tableSize / 2;
        // Offers need no clearing between batches: every round ends with each slot's minimum holder
        // resetting it. Locks are stamped with the batch number, so old ones expire by themselves.
        if (rebuild)
            for (int h = lid; h < tableSize; h += BTOCL_BATCH_WG) {
                tableKey[h] = BTOCL_EMPTY_BODY;
                tableBest[h] = BTOCL_NO_OFFER;
                tableLocked[h] = 0;
            }
        const int stamp = batch + 1;
        barrier(CLK_LOCAL_MEM_FENCE);
        const int firstNew = rebuild ? 0 : winSize - add;
        tableUsed = rebuild ? 2 * winSize : tableUsed + 2 * add;
        const int myEnd = min(winSize, myBegin + BTOCL_BATCH_PER_LANE);
        for (int e = myBegin; e < myEnd; ++e) {
            if (e >= firstNew) {
                const int a = winA[cur][e], b = winB[cur][e];
                winSlotA[cur][e] = a >= 0 ? batchTableSlot(tableKey, tableBits, a) : -1;
                winSlotB[cur][e] = b >= 0 ? batchTableSlot(tableKey, tableBits, b) : -1;
            }
            state[e] = BTOCL_BATCH_PENDING;
            owns[e] = 0;
            prio[e] = btoclBatchPriority(winIdx[cur][e], e, BTOCL_BATCH_WINDOW_BITS);
        }
        barrier(CLK_LOCAL_MEM_FENCE);

        for (int r = 0; r < rounds; ++r) {
            // Offer (locks are only read here, offers only atomically lowered). This round's flag was
            // last read two barriers ago.
            if (lid == 0) stillPending[r & 1] = 0;
            for (int e = myBegin; e < myEnd; ++e) {
                if (state[e] != BTOCL_BATCH_PENDING) continue;
                const int sa = winSlotA[cur][e], sb = winSlotB[cur][e];
                if ((sa >= 0 && tableLocked[sa] == stamp) || (sb >= 0 && tableLocked[sb] == stamp)) {
                    state[e] = BTOCL_BATCH_BLOCKED;
                    continue;
                }
                if (sa >= 0) atomic_min(&tableBest[sa], prio[e]);
                if (sb >= 0) atomic_min(&tableBest[sb], prio[e]);
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            // Decide (offers only read here).
            for (int e = myBegin; e < myEnd; ++e) {
                if (state[e] != BTOCL_BATCH_PENDING) continue;
                const int sa = winSlotA[cur][e], sb = winSlotB[cur][e];
                const bool wonA = sa < 0 || tableBest[sa] == prio[e];
                const bool wonB = sb < 0 || tableBest[sb] == prio[e];
                owns[e] = (sa >= 0 && wonA ? 1 : 0) | (sb >= 0 && wonB ? 2 : 0);
                if (wonA && wonB) state[e] = BTOCL_BATCH_SCHEDULED;
                else atomic_or(&stillPending[r & 1], 1);
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            // Lock the winners' bodies; each slot's minimum holder clears its offer for the next round.
            for (int e = myBegin; e < myEnd; ++e) {
                const int sa = winSlotA[cur][e], sb = winSlotB[cur][e];
                const int o = owns[e];
                if (o & 1) tableBest[sa] = BTOCL_NO_OFFER;
                if (o & 2) tableBest[sb] = BTOCL_NO_OFFER;
                owns[e] = 0;
                if (state[e] == BTOCL_BATCH_SCHEDULED) {
                    if (sa >= 0) tableLocked[sa] = stamp;
                    if (sb >= 0) tableLocked[sb] = stamp;
                }
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            if (!stillPending[r & 1]) break;  // uniform; further rounds would change nothing
        }

        // Output and compaction positions: prefix sums over lanes (lanes own contiguous slices).
        int nScheduled = 0;
        for (int e = myBegin; e < myEnd; ++e) nScheduled += state[e] == BTOCL_BATCH_SCHEDULED ? 1 : 0;
        laneScheduled[lid] = nScheduled;
        laneRest[lid] = max(0, myEnd - myBegin) - nScheduled;
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid == 0) {
            int runS = 0, runR = 0;
            for (int l = 0; l < BTOCL_BATCH_WG; ++l) {
                const int s = laneScheduled[l], r = laneRest[l];
                laneScheduled[l] = runS;
                laneRest[l] = runR;
                runS += s;
                runR += r;
            }
            totals[0] = runS;
            totals[1] = runR;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        const int nxt = 1 - cur;
        int atS = laneScheduled[lid], atR = laneRest[lid];
        for (int e = myBegin; e < myEnd; ++e) {
            if (state[e] == BTOCL_BATCH_SCHEDULED) {
                outBuf[atS++] = winIdx[cur][e];
            } else {
                winIdx[nxt][atR] = winIdx[cur][e];
                winA[nxt][atR] = winA[cur][e];
                winB[nxt][atR] = winB[cur][e];
                winSlotA[nxt][atR] = winSlotA[cur][e];
                winSlotB[nxt][atR] = winSlotB[cur][e];
                ++atR;
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        const int totalScheduled = totals[0], totalRest = totals[1];
        for (int i = lid; i < totalScheduled; i += BTOCL_BATCH_WG) solveOrder[offset + emitted + i] = outBuf[i];
        if (lid == 0) batchEnd[offset + batch] = offset + emitted + totalScheduled;
        emitted += totalScheduled;
        ++batch;
        winSize = totalRest;
        cur = nxt;
        barrier(CLK_LOCAL_MEM_FENCE);  // outBuf, totals and the lane sums are reused
    }
    barrier(CLK_GLOBAL_MEM_FENCE);  // every lane has read this group's record
    if (lid == 0) groups[gid].numBatches = batch;
}
