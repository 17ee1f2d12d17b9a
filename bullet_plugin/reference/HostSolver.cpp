#include "HostSolver.h"

#include <algorithm>
#include <cfloat>

namespace btocl {
namespace {

float dot3(const btoclFloat4& a, const btoclFloat4& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

void addScaled(btoclFloat4& target, const btoclFloat4& v, float s, const btoclFloat4* factor) {
    float x = v.x * s, y = v.y * s, z = v.z * s;
    if (factor) {
        x *= factor->x;
        y *= factor->y;
        z *= factor->z;
    }
    target.x += x;
    target.y += y;
    target.z += z;
}

btoclFloat4 mul(const btoclFloat4& a, const btoclFloat4& b) { return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }

struct RowSolver {
    StepProblem& p;
    bool applyFactors;

    void apply(int body, const btoclFloat4& linear, const btoclFloat4& angular, float impulse, bool push) {
        const btoclBody& b = p.bodies[size_t(body)];
        if (BTOCL_BODY_IS_DYNAMIC(b) == 0) return;
        btoclBodyDelta& d = p.deltas[size_t(body)];
        addScaled(push ? d.pushVelocity : d.deltaLinearVelocity, linear, impulse, applyFactors ? &b.linearFactor : nullptr);
        addScaled(push ? d.turnVelocity : d.deltaAngularVelocity, angular, impulse, applyFactors ? &b.angularFactor : nullptr);
    }

    float row(btoclRow& r, float lower, float upper, bool push) {
        const btoclBodyDelta& dA = p.deltas[size_t(r.bodyA)];
        const btoclBodyDelta& dB = p.deltas[size_t(r.bodyB)];
        const float jacDiagABInv = BTOCL_ROW_JAC_DIAG_INV(r);
        const float applied = push ? BTOCL_ROW_APPLIED_PUSH(r) : BTOCL_ROW_APPLIED(r);
        float deltaImpulse = (push ? BTOCL_ROW_RHS_PENETRATION(r) : BTOCL_ROW_RHS(r)) - applied * BTOCL_ROW_CFM(r);
        const float deltaVel1Dotn = dot3(r.contactNormal1, push ? dA.pushVelocity : dA.deltaLinearVelocity) +
                                    dot3(r.relpos1CrossNormal, push ? dA.turnVelocity : dA.deltaAngularVelocity);
        const float deltaVel2Dotn = dot3(r.contactNormal2, push ? dB.pushVelocity : dB.deltaLinearVelocity) +
                                    dot3(r.relpos2CrossNormal, push ? dB.turnVelocity : dB.deltaAngularVelocity);
        deltaImpulse -= deltaVel1Dotn * jacDiagABInv;
        deltaImpulse -= deltaVel2Dotn * jacDiagABInv;
        const float sum = applied + deltaImpulse;
        float newApplied = sum;
        if (sum < lower) {
            deltaImpulse = lower - applied;
            newApplied = lower;
        } else if (sum > upper) {
            deltaImpulse = upper - applied;
            newApplied = upper;
        }
        (push ? BTOCL_ROW_APPLIED_PUSH(r) : BTOCL_ROW_APPLIED(r)) = newApplied;
        apply(r.bodyA, mul(r.contactNormal1, p.bodies[size_t(r.bodyA)].invMass), r.angularComponentA, deltaImpulse, push);
        apply(r.bodyB, mul(r.contactNormal2, p.bodies[size_t(r.bodyB)].invMass), r.angularComponentB, deltaImpulse, push);
        return deltaImpulse * (1.0f / jacDiagABInv);
    }

    float frictionRows(const btoclConstraint& c, int kind) {
        float maxResidual2 = 0;
        for (int i = c.firstRow[kind]; i < c.firstRow[kind] + c.numRows[kind]; ++i) {
            btoclRow& r = p.rows[size_t(i)];
            const float total = BTOCL_ROW_APPLIED(p.rows[size_t(r.frictionIndex)]);
            if (!(total > 0)) continue;
            float limit = BTOCL_ROW_FRICTION(r) * total;
            if (kind == BTOCL_ROWS_ROLLING && limit > BTOCL_ROW_FRICTION(r)) limit = BTOCL_ROW_FRICTION(r);
            const float residual = row(r, -limit, limit, false);
            maxResidual2 = std::max(maxResidual2, residual * residual);
        }
        return maxResidual2;
    }

    // As the kernel: the normal rows (on push and turn velocities in the penetration pass), then in
    // the velocity pass the friction and rolling rows of the same constraint.
    float constraint(const btoclConstraint& c, int pass) {
        float maxResidual2 = 0;
        for (int i = c.firstRow[BTOCL_ROWS_NORMAL]; i < c.firstRow[BTOCL_ROWS_NORMAL] + c.numRows[BTOCL_ROWS_NORMAL]; ++i) {
            btoclRow& r = p.rows[size_t(i)];
            float residual = 0;
            if (pass == BTOCL_PASS_PENETRATION) {
                if (BTOCL_ROW_RHS_PENETRATION(r) == 0) continue;
                residual = row(r, BTOCL_ROW_LOWER(r), FLT_MAX, true);
            } else {
                residual = row(r, BTOCL_ROW_LOWER(r), FLT_MAX, false);
            }
            maxResidual2 = std::max(maxResidual2, residual * residual);
        }
        if (pass == BTOCL_PASS_VELOCITY) {
            maxResidual2 = std::max(maxResidual2, frictionRows(c, BTOCL_ROWS_FRICTION));
            maxResidual2 = std::max(maxResidual2, frictionRows(c, BTOCL_ROWS_ROLLING));
        }
        return maxResidual2;
    }

    // Every set in order, every group and batch in layout order.
    float pass(const BatchLayout& layout, int pass) {
        float maxResidual2 = 0;
        for (const btoclGroup& g : layout.groups) {
            int start = g.offset;
            for (int k = 0; k < g.numBatches; ++k) {
                const int end = layout.batchEnd[size_t(g.offset + k)];
                for (int i = start; i < end; ++i)
                    maxResidual2 = std::max(maxResidual2, constraint(p.constraints[size_t(layout.solveOrder[size_t(i)])], pass));
                start = end;
            }
        }
        return maxResidual2;
    }
};

}  // namespace

int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings) {
    RowSolver solver{p, (settings.flags & BTOCL_FLAG_APPLY_FACTORS) != 0};
    const bool track = (settings.flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0;
    if (settings.splitImpulse && p.numNormalRows > 0)
        for (int it = 0; it < settings.numIterations; ++it)
            if (solver.pass(layout, BTOCL_PASS_PENETRATION) <= settings.residualThreshold && track) break;
    int iterations = 0;
    for (int it = 0; it < settings.numIterations; ++it) {
        const float residual = solver.pass(layout, BTOCL_PASS_VELOCITY);
        ++iterations;
        if (track && residual <= settings.residualThreshold) break;
    }
    return iterations;
}

}  // namespace btocl
