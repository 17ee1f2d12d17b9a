// One step's problem gathered from a test world, and solved on the device: the steps the
// device-solve and row-setup tests share.
#pragma once

#include "BulletConversions.h"
#include "BulletGather.h"
#include "DeviceSolveProbe.h"
#include "DeviceSolver.h"
#include "PinnedHostMemory.h"
#include "TestDevice.h"
#include "TestWorld.h"

#include <BulletDynamics/ConstraintSolver/btSolverConstraint.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace btocl::test {

// One step gathered from the world's bodies, manifolds and joints as they are: the records, and
// the Bullet objects they came from.
struct GatheredStep {
    StepProblem problem;
    BulletStep bullet;
};
// streamPoints: the point records stored past the caches however few (StepGatherer::streamPointsAlways).
inline GatheredStep gatherStep(testworld::World& w, const btContactSolverInfo& info, RowSetup setup,
                               bool streamPoints = false) {
    StepGatherer builder;
    builder.streamPointsAlways(streamPoints);
    builder.begin(info, setup);
    btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
    builder.addBodies(&objects[0], objects.size());
    const std::vector<btPersistentManifold*> manifolds = w.manifolds();
    builder.addManifolds(manifolds.data(), int(manifolds.size()));
    std::vector<btTypedConstraint*> joints = w.constraints();
    builder.addJoints(joints.data(), int(joints.size()));
    GatheredStep g{builder.finish(), builder.bullet()};
    addSplitGeometry(g.problem, g.bullet);  // the tests split every step they gather
    builder.releaseBodies();
    return g;
}
inline StepProblem gatherProblem(testworld::World& w, const btContactSolverInfo& info, RowSetup setup,
                                 bool streamPoints = false) {
    return gatherStep(w, info, setup, streamPoints).problem;
}

// How the step's host arrays reach the device: handed over in place where it works in the
// host's memory (PoCL), copied, or copied from pinned memory (PinnedHostMemory), as on a GPU.
enum class Transfers { AsDevice, Copied, CopiedFromPinned };

// Uploads, arranges, solves and reads back a gathered problem on the device, in `layout`'s order,
// with the lanes of the path under test, launched as `mode` says.
// Returns the velocity iterations run; `rows`, when given, gets the rows as the device left them.
inline int solveOnDevice(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings,
                         RowArray* rows = nullptr, StepMode mode = StepMode::PerSet,
                         Transfers transfers = Transfers::AsDevice) {
    OclRuntime rt("");
    if (transfers != Transfers::AsDevice) rt.transferByCopy();
    PinnedHostMemory pinned(rt);
    // The arrays back on the heap however this ends: p outlives the pinned memory.
    struct BackToHeap {
        StepProblem& p;
        ~BackToHeap() { p.takeHostMemoryFrom(nullptr); }
    } backToHeap{p};
    if (transfers == Transfers::CopiedFromPinned) {
        p.takeHostMemoryFrom(&pinned);
        REQUIRE(pinned.bytesHeld() >= p.points.size() * sizeof(btoclContactPoint));
    }
    DevicePrimitives primitives(rt, testBackend());
    DeviceSolver solver(rt, primitives);
    const StepPlan plan = testPlan(mode, passScheduleOf(settings, p));
    DeviceSolveProbe probe(rt);
    solver.upload(p);
    const DeviceLayoutView view = probe.uploadLayout(layout);
    solver.arrange(p, view);
    solver.iterate(p, plan, view, settings);
    const int iterations = solver.download(p, plan, settings);
    if (rows) {
        const auto downloaded = DeviceSolveProbe::downloadRows(solver, p);
        rows->assign(downloaded.begin(), downloaded.end());
    }
    return iterations;
}

inline float relDiff(float a, float b) { return std::fabs(a - b) / std::max(1.0f, std::max(std::fabs(a), std::fabs(b))); }

inline float vectorGap(const btVector3& a, const btoclFloat4& b) {
    return std::max({relDiff(a.x(), b.x), relDiff(a.y(), b.y), relDiff(a.z(), b.z)});
}

// The largest relative gap between one of SI's rows and ours, over every field the solve reads.
inline float fieldGap(const btSolverConstraint& si, const btoclRow& r) {
    return std::max({vectorGap(si.m_contactNormal1, r.contactNormal1), vectorGap(si.m_relpos1CrossNormal, r.relpos1CrossNormal),
                     vectorGap(si.m_contactNormal2, r.contactNormal2), vectorGap(si.m_relpos2CrossNormal, r.relpos2CrossNormal),
                     vectorGap(si.m_angularComponentA, r.angularComponentA),
                     vectorGap(si.m_angularComponentB, r.angularComponentB), relDiff(si.m_rhs, BTOCL_ROW_RHS(r)),
                     relDiff(si.m_rhsPenetration, BTOCL_ROW_RHS_PENETRATION(r)), relDiff(si.m_cfm, BTOCL_ROW_CFM(r)),
                     relDiff(si.m_jacDiagABInv, BTOCL_ROW_JAC_DIAG_INV(r)), relDiff(si.m_lowerLimit, BTOCL_ROW_LOWER(r)),
                     relDiff(si.m_upperLimit, BTOCL_ROW_UPPER(r)), relDiff(si.m_appliedImpulse, BTOCL_ROW_APPLIED(r)),
                     relDiff(si.m_friction, BTOCL_ROW_FRICTION(r))});
}

}  // namespace btocl::test
