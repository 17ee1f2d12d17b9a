// Serial host references of the global split and the local batching (tests only).
#include "HostBatching.h"

#include "batch_priority.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace btocl {
namespace {

// Each group's constraints reordered by batch; batch k of the group ends at batchEnd[offset + k].
using GroupBatcher = void (*)(const std::vector<btoclConstraint>&, BatchLayout&, btoclGroup&, const SplitParams&, int);

void batchGroupGreedy(const std::vector<btoclConstraint>& constraints, BatchLayout& layout, btoclGroup& g,
                      const SplitParams&, int) {
    int* order = layout.solveOrder.data() + g.offset;
    // usedBatches[body] = the batches that already hold the body.
    std::unordered_map<int, std::vector<char>> used;
    std::vector<int> batchOf(size_t(g.count));
    int numBatches = 0;
    for (int i = 0; i < g.count; ++i) {
        const btoclConstraint& c = constraints[size_t(order[i])];
        const int a = dynamicBodyOf(c, 0), b = dynamicBodyOf(c, 1);
        std::vector<char>* ua = a >= 0 ? &used[a] : nullptr;
        std::vector<char>* ub = b >= 0 ? &used[b] : nullptr;
        int k = 0;
        auto taken = [&](int batch) {
            return (ua && batch < int(ua->size()) && (*ua)[size_t(batch)]) ||
                   (ub && batch < int(ub->size()) && (*ub)[size_t(batch)]);
        };
        while (taken(k)) ++k;
        for (std::vector<char>* u : {ua, ub})
            if (u) {
                if (int(u->size()) <= k) u->resize(size_t(k) + 1, 0);
                (*u)[size_t(k)] = 1;
            }
        batchOf[size_t(i)] = k;
        numBatches = std::max(numBatches, k + 1);
    }
    std::vector<int> sorted(order, order + g.count);
    std::vector<int> perm(size_t(g.count));
    for (int i = 0; i < g.count; ++i) perm[size_t(i)] = i;
    std::stable_sort(perm.begin(), perm.end(), [&](int x, int y) { return batchOf[size_t(x)] < batchOf[size_t(y)]; });
    for (int i = 0; i < g.count; ++i) order[i] = sorted[size_t(perm[size_t(i)])];
    std::vector<int> perBatch(size_t(numBatches), 0);
    for (int i = 0; i < g.count; ++i) ++perBatch[size_t(batchOf[size_t(i)])];
    int end = g.offset;
    for (int k = 0; k < numBatches; ++k) {
        end += perBatch[size_t(k)];
        layout.batchEnd[size_t(g.offset + k)] = end;
    }
    g.numBatches = numBatches;
}

// Mirrors kernels/batch.cl step for step (see buildBatchesHostStreamed in the header).
void batchGroupStreamed(const std::vector<btoclConstraint>& constraints, BatchLayout& layout, btoclGroup& g,
                        const SplitParams& params, int windowSize) {
    const std::vector<int> stream(layout.solveOrder.begin() + g.offset, layout.solveOrder.begin() + g.offset + g.count);
    std::vector<int> window;
    int next = 0, emitted = 0, batch = 0;
    enum { kPending, kBlocked, kScheduled };
    const int windowBits = btoclBatchWindowBits(windowSize);
    while (true) {
        while (int(window.size()) < windowSize && next < g.count) window.push_back(stream[size_t(next++)]);
        if (window.empty()) break;
        const int w = int(window.size());
        std::vector<int> state(size_t(w), kPending);
        std::unordered_set<int> locked;
        for (int round = 0; round < params.batchIterations; ++round) {
            std::unordered_map<int, int> best;
            for (int e = 0; e < w; ++e) {
                if (state[size_t(e)] != kPending) continue;
                const btoclConstraint& c = constraints[size_t(window[size_t(e)])];
                const int a = dynamicBodyOf(c, 0), b = dynamicBodyOf(c, 1);
                if ((a >= 0 && locked.count(a)) || (b >= 0 && locked.count(b))) {
                    state[size_t(e)] = kBlocked;
                    continue;
                }
                const int priority = btoclBatchPriority(window[size_t(e)], e, windowBits);
                for (int body : {a, b})
                    if (body >= 0) {
                        auto it = best.find(body);
                        if (it == best.end() || priority < it->second) best[body] = priority;
                    }
            }
            std::vector<int> wonNow;
            for (int e = 0; e < w; ++e) {
                if (state[size_t(e)] != kPending) continue;
                const btoclConstraint& c = constraints[size_t(window[size_t(e)])];
                const int a = dynamicBodyOf(c, 0), b = dynamicBodyOf(c, 1);
                const int priority = btoclBatchPriority(window[size_t(e)], e, windowBits);
                if ((a < 0 || best[a] == priority) && (b < 0 || best[b] == priority)) wonNow.push_back(e);
            }
            for (int e : wonNow) {
                state[size_t(e)] = kScheduled;
                const btoclConstraint& c = constraints[size_t(window[size_t(e)])];
                for (int body : {dynamicBodyOf(c, 0), dynamicBodyOf(c, 1)})
                    if (body >= 0) locked.insert(body);
            }
        }
        std::vector<int> rest;
        for (int e = 0; e < w; ++e) {
            if (state[size_t(e)] == kScheduled)
                layout.solveOrder[size_t(g.offset + emitted++)] = window[size_t(e)];
            else
                rest.push_back(window[size_t(e)]);
        }
        layout.batchEnd[size_t(g.offset + batch++)] = g.offset + emitted;
        window.swap(rest);
    }
    g.numBatches = batch;
}

BatchLayout buildWith(const std::vector<btoclConstraint>& constraints, const std::vector<SplitBody>& bodies,
                      const SplitParams& params, GroupBatcher batcher, int windowSize) {
    checkSplitParams(params);
    BatchLayout layout = splitHost(constraints, bodies, params);
    for (btoclGroup& g : layout.groups) batcher(constraints, layout, g, params, windowSize);
    return layout;
}

}  // namespace

BatchLayout buildBatchesHost(const std::vector<btoclConstraint>& constraints, const std::vector<SplitBody>& bodies,
                             const SplitParams& params) {
    return buildWith(constraints, bodies, params, batchGroupGreedy, 0);
}

BatchLayout buildBatchesHostStreamed(const std::vector<btoclConstraint>& constraints,
                                     const std::vector<SplitBody>& bodies, const SplitParams& params,
                                     int windowSize) {
    if (windowSize < 1) throw btOpenCLSolverError("btOpenCLConstraintSolver: the batching window must hold a constraint");
    return buildWith(constraints, bodies, params, batchGroupStreamed, windowSize);
}

int greedyBatchCount(const std::vector<btoclConstraint>& constraints, const int* indices, int count) {
    BatchLayout scratch;
    scratch.solveOrder.assign(indices, indices + count);
    scratch.batchEnd.assign(size_t(count), 0);
    btoclGroup g{0, count, 0, 0};
    batchGroupGreedy(constraints, scratch, g, SplitParams{}, 0);
    return g.numBatches;
}

}  // namespace btocl
