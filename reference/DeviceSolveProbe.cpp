#include "DeviceSolveProbe.h"

namespace btocl {

DeviceLayoutView DeviceSolveProbe::uploadLayout(const BatchLayout& layout) {
    m_groups.write(m_rt, layout.groups);
    m_solveOrder.write(m_rt, layout.solveOrder);
    m_batchEnd.write(m_rt, layout.batchEnd);
    m_setGroupStart.write(m_rt, layout.setGroupStart.data(), layout.setGroupStart.size());
    DeviceLayoutView view;
    view.groups = &m_groups.buffer();
    view.solveOrder = &m_solveOrder.buffer();
    view.batchEnd = &m_batchEnd.buffer();
    view.setGroupStart = layout.setGroupStart;
    view.setGroupStartOnDevice = &m_setGroupStart.buffer();
    return view;
}

HostArrangement DeviceSolveProbe::downloadArrangement(const DeviceSolver& solver, const StepProblem& p) {
    HostArrangement a;
    a.placed = solver.m_placed.read(solver.m_rt, p.constraints.size());
    a.rowMap = solver.m_rowMap.read(solver.m_rt, size_t(p.numRows()));
    return a;
}

std::vector<btoclRow> DeviceSolveProbe::downloadRows(const DeviceSolver& solver, const StepProblem& p) {
    const OclRuntime& rt = solver.m_rt;
    const size_t n = size_t(p.numRows());
    const std::vector<btoclSolveRow> placed = solver.m_rows.read(rt, n);
    const std::vector<int> map = solver.m_rowMap.read(rt, n), normalOf = solver.m_normalOfRow.read(rt, n);
    const std::vector<float> applied = solver.m_applied.read(rt, n), pushApplied = solver.m_pushApplied.read(rt, n);
    std::vector<int> unmap(n);
    for (size_t r = 0; r < n; ++r) unmap[size_t(map[r])] = int(r);
    // Each gather row's kind and bodies: contact rows from their point, joint rows from their joint.
    std::vector<btoclRow> rows(n);
    for (size_t g = 0; g < n; ++g) {
        const size_t at = size_t(map[g]);
        const btoclSolveRow& s = placed[at];
        btoclRow& r = rows[g];
        const int kind = btoclKindOfRow(&p.regions, int(g));
        r.frictionIndex = kind == BTOCL_ROWS_FRICTION || kind == BTOCL_ROWS_ROLLING ? unmap[size_t(normalOf[at])] : -1;
        if (kind == BTOCL_ROWS_JOINT) {  // set up on the host: their bodies are in p.rows
            const btoclRow& hostRow = p.rows[g - size_t(p.hostRowBase())];
            r.bodyA = hostRow.bodyA;
            r.bodyB = hostRow.bodyB;
        } else {
            const btoclContactPoint& pt = p.points[size_t(kind == BTOCL_ROWS_NORMAL ? int(g) : r.frictionIndex)];
            r.bodyA = pt.bodyA;
            r.bodyB = pt.bodyB;
        }
        // As SI holds a contact row: no linear Jacobian on a side without a rigid body.
        const bool rigidA = kind == BTOCL_ROWS_JOINT || BTOCL_BODY_IS_RIGID(p.bodies[size_t(r.bodyA)]) != 0;
        const bool rigidB = kind == BTOCL_ROWS_JOINT || BTOCL_BODY_IS_RIGID(p.bodies[size_t(r.bodyB)]) != 0;
        const btoclFloat4 zero{0, 0, 0, 0};
        const btoclFloat4 normal{s.normal.x, s.normal.y, s.normal.z, 0};
        const btoclFloat4 negated{-s.normal.x, -s.normal.y, -s.normal.z, 0};
        r.contactNormal1 = rigidA ? normal : zero;
        r.contactNormal2 = rigidB ? negated : zero;
        r.relpos1CrossNormal = {s.relpos1CrossNormal.x, s.relpos1CrossNormal.y, s.relpos1CrossNormal.z, 0};
        r.relpos2CrossNormal = {s.relpos2CrossNormal.x, s.relpos2CrossNormal.y, s.relpos2CrossNormal.z, 0};
        r.angularComponentA = {s.angularComponentA.x, s.angularComponentA.y, s.angularComponentA.z, 0};
        r.angularComponentB = {s.angularComponentB.x, s.angularComponentB.y, s.angularComponentB.z, 0};
        r.impulses = zero;
        BTOCL_ROW_RHS(r) = BTOCL_SOLVE_ROW_RHS(s);
        BTOCL_ROW_CFM(r) = BTOCL_SOLVE_ROW_CFM(s);
        BTOCL_ROW_JAC_DIAG_INV(r) = BTOCL_SOLVE_ROW_JAC_DIAG_INV(s);
        BTOCL_ROW_APPLIED(r) = applied[at];
        BTOCL_ROW_APPLIED_PUSH(r) = pushApplied[at];
        if (kind == BTOCL_ROWS_JOINT) {
            BTOCL_ROW_LOWER(r) = BTOCL_SOLVE_ROW_LOWER(s);
            BTOCL_ROW_UPPER(r) = BTOCL_SOLVE_ROW_UPPER(s);
        } else if (kind == BTOCL_ROWS_NORMAL) {
            BTOCL_ROW_RHS_PENETRATION(r) = BTOCL_SOLVE_ROW_RHS_PENETRATION(s);
            BTOCL_ROW_LOWER(r) = 0;
            BTOCL_ROW_UPPER(r) = 1e10f;
            BTOCL_ROW_FRICTION(r) = BTOCL_POINT_FRICTION(p.points[g]);
        } else {
            BTOCL_ROW_FRICTION(r) = BTOCL_SOLVE_ROW_FRICTION(s);
            BTOCL_ROW_LOWER(r) = -BTOCL_ROW_FRICTION(r);
            BTOCL_ROW_UPPER(r) = BTOCL_ROW_FRICTION(r);
        }
    }
    return rows;
}

}  // namespace btocl
