// Global split and local batch creation on the device (kernels/split.cl, kernels/batch.cl).
// The output equals the serial reference buildBatchesHostStreamed(constraints, bodies, params,
// windowSize(params.workGroupSize)) bit for bit (reference/HostBatching.h; tests/test_batching.cpp).
#pragma once

#include "BatchLayout.h"
#include "DeviceBuffer.h"
#include "DevicePrimitives.h"
#include "KernelWarmUp.h"
#include "OclRuntime.h"
#include "SplitPlan.h"
#include "StepPlan.h"
#include "split_grid.h"

#include <array>
#include <map>
#include <vector>

namespace btocl {

struct DeviceLayoutStats {
    int numConstraints = 0;
    int numCellGroups = 0;          // groups of sets 0..3 (the overflow group is not a cell)
    int numBatchesMax = 0;          // over all groups, overflow included
    double numBatchesMean = 0;      // over all groups, overflow included
    int numOverflowConstraints = 0;
    float cellSize = 0;
};

class DeviceLayout {
public:
    // Builds the split program and the batch program for 64 lanes. `rt` and `primitives` (the sort
    // and scan) must outlive this object.
    DeviceLayout(const OclRuntime& rt, DevicePrimitives& primitives);

    // Lays constraints [0, n), already on the device, out as `plan` says: one group (a whole step)
    // or the global split's groups, and each group as local batches or as one run. Enqueues
    // everything on rt.queue(); the one blocking read is 8 ints after the split (set starts,
    // overflow count, cell edge), needed to size the launches over groups (none where the plan
    // reads the set starts on the device, none for one group): then setGroupStart(), numGroups()
    // and stats() are valid only once the queue has finished. The split's commands are timed as
    // DevicePhase::Split, the batch kernel's as DevicePhase::Batch. bodies: one entry per body
    // index the constraints use. Throws btOpenCLSolverError on bad parameters or a device error.
    void build(const DeviceBuffer<btoclConstraint>& constraints, int n, const std::vector<SplitBody>& bodies,
               const SplitParams& params, const StepPlan& plan);

    // Takes a split made on the host (HostSplit.h) with one run a group, for a plan without local
    // batches: uploads it where build() would have left the device's. `layout` must live, unchanged,
    // until the queue has finished. Throws btOpenCLSolverError for a layout with batches.
    void upload(const BatchLayout& layout, const StepPlan& plan);

    // The layout of the last build, on the device (valid until the next build).
    const DeviceBuffer<int>& solveOrder() const { return m_localBatches ? m_solveOrder : m_sorted; }
    const DeviceBuffer<int>& batchEnd() const { return m_batchEnd; }
    const DeviceBuffer<btoclGroup>& groups() const { return m_groups; }
    const std::array<int, BTOCL_NUM_SETS + 2>& setGroupStart() const;
    int numGroups() const { return setGroupStart()[BTOCL_NUM_SETS + 1]; }
    // The set starts on the device: BTOCL_NUM_SETS + 2 ints, as setGroupStart().
    const DeviceBuffer<int>& setGroupStartBuffer() const { return m_summary; }

    // Valid once the queue has finished the build's commands (the batch counts are read back
    // without a wait of their own).
    const DeviceLayoutStats& stats() const;

    // Host copy of the layout, for tests and validation (blocking).
    BatchLayout download() const;

    // Constraints per streamed chunk of the batch kernel for a work-group size (fits local memory).
    int windowSize(int workGroupSize) const;

    // Launches every kernel of the split, and with `lanes`' local batches the batch kernel for
    // its work-group size, in their launch shapes, on no work (KernelWarmUp.h). Touches none of
    // this object's buffers.
    void warmUp(KernelWarmUp& warm, const GroupLanes& lanes);

private:
    struct BatchProgram {
        cl::Program program;
        cl::Kernel kernel;
        int window = 0;
    };
    BatchProgram& batchProgram(int workGroupSize);
    size_t boundsParts() const;
    void startLayout(const StepPlan& plan, int n);
    void writeSetStarts();
    void layOutOneGroup(int n);
    void takeSummary(const int* summary) const;
    void split(const DeviceBuffer<btoclConstraint>& constraints, int n, const std::vector<SplitBody>& bodies,
               const SplitParams& params);

    const OclRuntime& m_rt;
    DevicePrimitives& m_prims;  // the stable sort by cell key and the scan over key bins
    bool m_localBatches = false, m_setStartsOnDevice = false;  // the plan of the last build
    cl::Kernel m_splitBoundsAndGrid, m_splitKeys, m_splitMarkBins, m_splitWriteGroups;
    std::map<int, BatchProgram> m_batchPrograms;

    DeviceBuffer<btoclSplitGrid> m_grid;
    DeviceBuffer<cl_uchar> m_overflowBody;
    DeviceBuffer<cl_uint> m_keys;
    DeviceBuffer<int> m_sorted, m_binStart, m_binEnd, m_groupOfBin, m_summary;
    DeviceBuffer<int> m_solveOrder, m_batchEnd;
    DeviceBuffer<btoclGroup> m_groups;
    std::vector<cl_uchar> m_overflowHost;  // lives until its upload is done
    std::vector<btoclGroup> m_groupsHost;  // the batch counts, read back with the step's last wait
    std::vector<int> m_identityHost;       // a one-group layout's order, likewise
    btoclGroup m_oneGroupHost{};
    std::array<int, BTOCL_NUM_SETS + 4> m_summaryHost{};  // the split's summary, read back (or a one-group layout's)
    int m_n = 0;
    mutable std::array<int, BTOCL_NUM_SETS + 2> m_setGroupStart{};
    mutable bool m_summaryPending = false;  // read back with the step's last wait, not taken yet
    mutable DeviceLayoutStats m_stats;
    mutable bool m_statsReady = true;
};

}  // namespace btocl
