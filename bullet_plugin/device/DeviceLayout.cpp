#include "DeviceLayout.h"

#include "batch_priority.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace btocl {
namespace {

constexpr size_t kBoundsChunks = 128;  // work-items of the bounding-box reduction, at most
constexpr int kSummaryInts = BTOCL_NUM_SETS + 4;
constexpr size_t kLanes = 64;        // local size of the launches whose global size follows n
constexpr int kPreferredWindow = 512; // constraints per streamed chunk; big enough that a batch
                                      // of a dense cell is not cut short by the window

int tableBitsFor(int window) {
    int bits = 1;
    while ((1 << bits) < 4 * window) ++bits;  // at most 2 bodies per constraint: load <= 1/2
    return bits;
}

size_t batchLocalBytes(int wg, int window) {
    return sizeof(int) * (size_t(window) * 14 + size_t(3) * (size_t(1) << tableBitsFor(window)) + 2 * size_t(wg) + 2);
}

}  // namespace

DeviceLayout::DeviceLayout(const OclRuntime& rt, DevicePrimitives& primitives) : m_rt(rt), m_prims(primitives) {
    // Built with correctly rounded division: the grid's 1 / cell must equal the host reference's
    // bit for bit.
    const cl::Program& split = rt.stepProgram();
    m_splitBoundsAndGrid = rt.makeKernel(split, "splitBoundsAndGrid");
    m_splitKeys = rt.makeKernel(split, "splitKeys");
    m_splitMarkBins = rt.makeKernel(split, "splitMarkBins");
    m_splitWriteGroups = rt.makeKernel(split, "splitWriteGroups");
    // The batch kernel is built for its work-group size when a step or the warm-up first asks:
    // the serial path never does.
}

// Work-items of the bounds' one work-group: each takes a chunk of the constraints.
size_t DeviceLayout::boundsParts() const { return std::min<size_t>(kBoundsChunks, m_rt.maxWorkGroupSize()); }

int DeviceLayout::windowSize(int wg) const {
    if (wg < 1 || size_t(wg) > m_rt.maxWorkGroupSize())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: workGroupSize " + std::to_string(wg) +
                                  " is outside 1.." + std::to_string(m_rt.maxWorkGroupSize()) + " on " +
                                  m_rt.deviceName());
    int window = wg * std::max(1, (kPreferredWindow + wg - 1) / wg);
    while (batchLocalBytes(wg, window) > m_rt.localMemSize() && window > wg) window = std::max(wg, window / 2 / wg * wg);
    if (batchLocalBytes(wg, window) > m_rt.localMemSize())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: the batch kernel for workGroupSize " + std::to_string(wg) +
                                  " needs " + std::to_string(batchLocalBytes(wg, window)) +
                                  " bytes of local memory; the device has " + std::to_string(m_rt.localMemSize()));
    return window;
}

DeviceLayout::BatchProgram& DeviceLayout::batchProgram(int wg) {
    auto it = m_batchPrograms.find(wg);
    if (it != m_batchPrograms.end()) return it->second;
    BatchProgram p;
    p.window = windowSize(wg);
    const std::string options = "-DBTOCL_BATCH_WG=" + std::to_string(wg) + " -DBTOCL_BATCH_WINDOW=" + std::to_string(p.window) +
                                " -DBTOCL_BATCH_TABLE_BITS=" + std::to_string(tableBitsFor(p.window)) +
                                " -DBTOCL_BATCH_WINDOW_BITS=" + std::to_string(btoclBatchWindowBits(p.window));
    p.program = m_rt.buildProgramFile("batch.cl", options);
    p.kernel = m_rt.makeKernel(p.program, "batchGroups");
    return m_batchPrograms.emplace(wg, std::move(p)).first->second;
}

void DeviceLayout::build(const DeviceBuffer<btoclConstraint>& constraints, int n,
                          const std::vector<SplitBody>& bodies, const SplitParams& params, const StepPlan& plan) {
    checkSplitParams(params);
    if (n < 0 || size_t(n) > constraints.capacity())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: " + std::to_string(n) +
                                  " constraints asked of a buffer of " + std::to_string(constraints.capacity()));
    startLayout(plan, n);
    if (n == 0) return;
    m_rt.beginPhase(DevicePhase::Split);
    for (DeviceBuffer<int>* b : {&m_sorted, &m_solveOrder, &m_batchEnd}) b->reserve(m_rt, size_t(n));
    m_groups.reserve(m_rt, size_t(std::min(n, BTOCL_SPLIT_NUM_KEYS)));
    if (plan.oneGroup())
        layOutOneGroup(n);
    else
        split(constraints, n, bodies, params);
    if (!m_localBatches) return;  // the split (or the one group) wrote one run per group
    m_rt.beginPhase(DevicePhase::Batch);
    BatchProgram& batch = batchProgram(params.workGroupSize);
    setArgs(batch.kernel, constraints.buffer(), m_sorted.buffer(), m_groups.buffer(), params.batchIterations,
            m_solveOrder.buffer(), m_batchEnd.buffer());
    m_rt.launch(batch.kernel, size_t(numGroups()) * size_t(params.workGroupSize), size_t(params.workGroupSize),
                "enqueueing batchGroups");
    m_groupsHost.resize(size_t(numGroups()));
    m_groups.enqueueRead(m_rt, m_groupsHost.data(), m_groupsHost.size());
}

void DeviceLayout::upload(const BatchLayout& layout, const StepPlan& plan) {
    if (!layout.serialRuns || plan.localBatches())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a host split is taken with one run a group only");
    const int n = int(layout.solveOrder.size());
    startLayout(plan, n);
    m_setGroupStart = layout.setGroupStart;
    m_stats.numCellGroups = layout.setGroupStart[BTOCL_NUM_SETS];
    m_stats.numOverflowConstraints = layout.numOverflowConstraints;
    m_stats.cellSize = layout.cellSize;
    if (n == 0) return;
    m_rt.beginPhase(DevicePhase::Split);
    m_sorted.enqueueWrite(m_rt, layout.solveOrder);
    m_batchEnd.enqueueWrite(m_rt, layout.batchEnd);
    m_groups.enqueueWrite(m_rt, layout.groups);
    if (m_setStartsOnDevice) writeSetStarts();
}

// What every layout starts from: the plan's, nothing taken from the last step.
void DeviceLayout::startLayout(const StepPlan& plan, int n) {
    m_localBatches = plan.localBatches();
    m_setStartsOnDevice = plan.setStartsOnDevice();
    m_n = n;
    m_summaryPending = false;
    m_setGroupStart.fill(0);
    m_stats = DeviceLayoutStats{};
    m_stats.numConstraints = n;
    m_statsReady = false;
    m_groupsHost.clear();
}

// The set starts the host knows, for a launch that reads them on the device.
void DeviceLayout::writeSetStarts() {
    std::copy(m_setGroupStart.begin(), m_setGroupStart.end(), m_summaryHost.begin());
    m_summary.enqueueWrite(m_rt, m_summaryHost.data(), m_setGroupStart.size());
}

// Every constraint in group 0 of set 0, in gather order.
void DeviceLayout::layOutOneGroup(int n) {
    m_identityHost.resize(size_t(n));
    for (int i = 0; i < n; ++i) m_identityHost[size_t(i)] = i;
    m_sorted.enqueueWrite(m_rt, m_identityHost);
    m_oneGroupHost = btoclGroup{0, n, m_localBatches ? 0 : 1, 0};
    m_groups.enqueueWrite(m_rt, &m_oneGroupHost, 1);
    if (!m_localBatches) m_batchEnd.fill(m_rt, n, 1);
    m_setGroupStart.fill(1);
    m_setGroupStart[0] = 0;
    if (m_setStartsOnDevice) writeSetStarts();
}

void DeviceLayout::takeSummary(const int* summary) const {
    for (int s = 0; s < BTOCL_NUM_SETS + 2; ++s) m_setGroupStart[size_t(s)] = summary[s];
    m_stats.numCellGroups = m_setGroupStart[BTOCL_NUM_SETS];
    m_stats.numOverflowConstraints = summary[BTOCL_NUM_SETS + 2];
    std::memcpy(&m_stats.cellSize, &summary[BTOCL_NUM_SETS + 3], sizeof(float));
    m_summaryPending = false;
}

const std::array<int, BTOCL_NUM_SETS + 2>& DeviceLayout::setGroupStart() const {
    if (m_summaryPending) takeSummary(m_summaryHost.data());  // the queue has finished: read back
    return m_setGroupStart;
}

// The global split (docs/architecture.md): cell keys, a stable sort by key, one group per non-empty cell.
void DeviceLayout::split(const DeviceBuffer<btoclConstraint>& constraints, int n, const std::vector<SplitBody>& bodies,
                          const SplitParams& params) {
    const OclRuntime& rt = m_rt;
    const SplitBodiesPlan plan = planSplitBodies(bodies, params);
    m_overflowHost.assign(plan.overflowBody.begin(), plan.overflowBody.end());
    if (m_overflowHost.empty()) m_overflowHost.push_back(0);  // no zero-sized buffers
    m_overflowBody.enqueueWrite(rt, m_overflowHost);
    m_grid.reserve(rt, 1);
    m_keys.reserve(rt, size_t(n));
    m_summary.reserve(rt, kSummaryInts);

    const size_t parts = boundsParts();
    const int chunk = int((size_t(n) + parts - 1) / parts);
    const cl::Buffer& cb = constraints.buffer();

    setArgs(m_splitBoundsAndGrid, cb, n, chunk, plan.baseCellSize, m_grid.buffer(), cl::Local(parts * sizeof(cl_float4)),
            cl::Local(parts * sizeof(cl_float4)));
    m_rt.launch(m_splitBoundsAndGrid, parts, parts, "enqueueing splitBoundsAndGrid");
    setArgs(m_splitKeys, cb, n, m_overflowBody.buffer(), int(bodies.size()), m_grid.buffer(), m_keys.buffer(),
            m_sorted.buffer());
    m_rt.launch(m_splitKeys, size_t(n), kLanes, "enqueueing splitKeys");

    // Stable sort by key (kernels/primitives.cl); keys < 2^16 by construction, so no key check.
    m_prims.sortByKeySmallRange(m_keys.buffer(), m_sorted.buffer(), size_t(n), BTOCL_SPLIT_NUM_KEYS, false);

    // Groups: one per non-empty key, numbered by a scan over the flags of the key bins. The bins
    // start empty: filled, not cleared by a kernel (one kernel fewer to compile).
    for (DeviceBuffer<int>* b : {&m_binStart, &m_binEnd, &m_groupOfBin}) b->fill(rt, 0, BTOCL_SPLIT_NUM_KEYS);
    setArgs(m_splitMarkBins, m_keys.buffer(), n, m_binStart.buffer(), m_binEnd.buffer(), m_groupOfBin.buffer());
    m_rt.launch(m_splitMarkBins, size_t(n), kLanes, "enqueueing splitMarkBins");
    m_prims.exclusiveScan(m_groupOfBin.buffer(), m_groupOfBin.buffer(), BTOCL_SPLIT_NUM_KEYS);
    setArgs(m_splitWriteGroups, m_binStart.buffer(), m_binEnd.buffer(), m_groupOfBin.buffer(), m_grid.buffer(),
            m_groups.buffer(), m_localBatches ? 0 : 1, m_batchEnd.buffer(), m_summary.buffer());
    m_rt.launch(m_splitWriteGroups, BTOCL_SPLIT_NUM_KEYS, 0, "enqueueing splitWriteGroups");

    if (m_setStartsOnDevice) {  // read with the step's last wait
        m_summary.enqueueRead(rt, m_summaryHost.data(), kSummaryInts);
        m_summaryPending = true;
        return;
    }
    // The one read-back: the launches over groups need the number of groups.
    m_summary.read(rt, m_summaryHost.data(), kSummaryInts);
    takeSummary(m_summaryHost.data());
}

void DeviceLayout::warmUp(KernelWarmUp& warm, const GroupLanes& lanes) {
    constexpr size_t grid = KernelWarmUp::kGrid;
    const cl::Buffer z = warm.zeros(4096);
    const size_t binBytes = sizeof(int) * BTOCL_SPLIT_NUM_KEYS;
    const cl::Buffer binStart = warm.zeros(binBytes), binEnd = warm.zeros(binBytes), flags = warm.zeros(binBytes);
    const int none = 0;
    const size_t parts = boundsParts();
    // A grid from no bounds (one cell), which the group writer reads.
    const cl::Buffer grid1 = warm.zeros(sizeof(btoclSplitGrid));
    setArgs(m_splitBoundsAndGrid, z, none, none, 1.0f, grid1, cl::Local(parts * sizeof(cl_float4)),
            cl::Local(parts * sizeof(cl_float4)));
    warm.launch(m_splitBoundsAndGrid, parts, parts);
    setArgs(m_splitKeys, z, none, z, none, grid1, z, z);
    warm.launch(m_splitKeys, grid, kLanes);
    setArgs(m_splitMarkBins, z, none, binStart, binEnd, flags);
    warm.launch(m_splitMarkBins, grid, kLanes);
    setArgs(m_splitWriteGroups, binStart, binEnd, flags, grid1, z, lanes.localBatches ? 0 : 1, z, z);  // no bin holds any
    warm.launch(m_splitWriteGroups, BTOCL_SPLIT_NUM_KEYS, 0);
    if (!lanes.localBatches) return;
    // Empty groups: the batch kernel finds nothing to batch.
    const size_t wg = size_t(lanes.lanes);
    const cl::Buffer groups = warm.zeros(sizeof(btoclGroup) * (grid / wg));
    BatchProgram& batch = batchProgram(lanes.lanes);
    setArgs(batch.kernel, z, z, groups, none, z, z);
    warm.launch(batch.kernel, grid, wg);
}

const DeviceLayoutStats& DeviceLayout::stats() const {
    setGroupStart();  // takes a summary read back with the step's last wait
    if (m_statsReady) return m_stats;
    // Without local batches every group is one run.
    long long sum = m_groupsHost.empty() ? numGroups() : 0;
    m_stats.numBatchesMax = numGroups() > 0 ? 1 : 0;
    for (const btoclGroup& g : m_groupsHost) {
        m_stats.numBatchesMax = std::max(m_stats.numBatchesMax, g.numBatches);
        sum += g.numBatches;
    }
    m_stats.numBatchesMean = numGroups() == 0 ? 0.0 : double(sum) / double(numGroups());
    m_statsReady = true;
    return m_stats;
}

BatchLayout DeviceLayout::download() const {
    m_rt.finish("batching constraints on the device");
    BatchLayout layout;
    layout.solveOrder = solveOrder().read(m_rt, size_t(m_n));
    layout.batchEnd = m_batchEnd.read(m_rt, size_t(m_n));
    layout.groups = m_groups.read(m_rt, size_t(numGroups()));
    layout.setGroupStart = setGroupStart();
    layout.cellSize = m_stats.cellSize;
    layout.numOverflowConstraints = m_stats.numOverflowConstraints;
    layout.serialRuns = !m_localBatches;
    return layout;
}

}  // namespace btocl
