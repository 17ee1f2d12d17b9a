#include "LaneRowSetup.h"

#include "HostSolve.h"
#include "LaneVectors.h"

#include <cfloat>
#include <cstddef>

namespace btocl {
namespace {

// What a lane past its points reads (its rows are not stored).
alignas(16) const btoclContactPoint kNoPoint{};

// Three lanes' vectors: a 3-vector in each lane.
struct Vec3 {
    Lanes x, y, z;
};
BTOCL_LANES_INLINE Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
BTOCL_LANES_INLINE Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
BTOCL_LANES_INLINE Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
BTOCL_LANES_INLINE Vec3 operator*(Vec3 a, Lanes s) { return {a.x * s, a.y * s, a.z * s}; }
BTOCL_LANES_INLINE Lanes dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
BTOCL_LANES_INLINE Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// b where m is set, else a (each lane's `m ? b : a`).
BTOCL_LANES_INLINE Vec3 select(Vec3 a, Vec3 b, LaneMask m) { return {select(a.x, b.x, m), select(a.y, b.y, m), select(a.z, b.z, m)}; }
BTOCL_LANES_INLINE Vec3 zero3() { return {splat(0.0f), splat(0.0f), splat(0.0f)}; }
BTOCL_LANES_INLINE Lanes sqrtLanes(Lanes v) { return (Lanes)_mm256_sqrt_ps((__m256)v); }
BTOCL_LANES_INLINE Lanes absLanes(Lanes v) { return (Lanes)((LaneMask)v & 0x7fffffff); }

// Eight float4s, the i-th at p[i], as their x, y, z and w lanes.
struct Float4Lanes {
    Lanes x, y, z, w;
    BTOCL_LANES_INLINE Vec3 xyz() const { return {x, y, z}; }
};
BTOCL_LANES_INLINE Float4Lanes transpose(const btoclFloat4* const* p, size_t offset) {
    auto at = [&](int i) { return _mm_load_ps(reinterpret_cast<const float*>(reinterpret_cast<const char*>(p[i]) + offset)); };
    const __m256 r0 = _mm256_insertf128_ps(_mm256_castps128_ps256(at(0)), at(4), 1);
    const __m256 r1 = _mm256_insertf128_ps(_mm256_castps128_ps256(at(1)), at(5), 1);
    const __m256 r2 = _mm256_insertf128_ps(_mm256_castps128_ps256(at(2)), at(6), 1);
    const __m256 r3 = _mm256_insertf128_ps(_mm256_castps128_ps256(at(3)), at(7), 1);
    const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1);
    const __m256 t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3);
    return {(Lanes)_mm256_shuffle_ps(t0, t2, 0x44), (Lanes)_mm256_shuffle_ps(t0, t2, 0xee),
            (Lanes)_mm256_shuffle_ps(t1, t3, 0x44), (Lanes)_mm256_shuffle_ps(t1, t3, 0xee)};
}
#define BTOCL_FIELD_LANES(records, type, field) \
    transpose(reinterpret_cast<const btoclFloat4* const*>(records), offsetof(type, field))

// A side's bodies as the row setup reads them (btoclContactFrameOf, btoclNormalRow, ...).
struct SetupBodies {
    Vec3 centerOfMass, linear, angular, force, torque, row0, row1, row2, angularFactor, scale0, scale1, scale2;
    Lanes invMass;
    LaneMask rigid, scaled;
};
BTOCL_LANES_INLINE SetupBodies loadSetupBodies(const btoclBody* const* b) {
    SetupBodies s;
    const Float4Lanes factor = BTOCL_FIELD_LANES(b, btoclBody, angularFactor);
    s.angularFactor = factor.xyz();
    s.rigid = factor.w != 0.0f;
    s.invMass = BTOCL_FIELD_LANES(b, btoclBody, linearFactor).w;
    s.centerOfMass = BTOCL_FIELD_LANES(b, btoclBody, centerOfMass).xyz();
    s.linear = BTOCL_FIELD_LANES(b, btoclBody, linearVelocity).xyz();
    s.angular = BTOCL_FIELD_LANES(b, btoclBody, angularVelocity).xyz();
    s.force = BTOCL_FIELD_LANES(b, btoclBody, externalForceImpulse).xyz();
    s.torque = BTOCL_FIELD_LANES(b, btoclBody, externalTorqueImpulse).xyz();
    s.row0 = BTOCL_FIELD_LANES(b, btoclBody, invInertiaRow0).xyz();
    s.row1 = BTOCL_FIELD_LANES(b, btoclBody, invInertiaRow1).xyz();
    s.row2 = BTOCL_FIELD_LANES(b, btoclBody, invInertiaRow2).xyz();
    const Float4Lanes scale0 = BTOCL_FIELD_LANES(b, btoclBody, angularScaleRow0);
    s.scale0 = scale0.xyz();
    s.scaled = scale0.w != 0.0f;
    s.scale1 = BTOCL_FIELD_LANES(b, btoclBody, angularScaleRow1).xyz();
    s.scale2 = BTOCL_FIELD_LANES(b, btoclBody, angularScaleRow2).xyz();
    return s;
}

// btoclAngularComponent.
BTOCL_LANES_INLINE Vec3 angularComponent(const SetupBodies& b, Vec3 axis) {
    return {dot(b.row0, axis) * b.angularFactor.x, dot(b.row1, axis) * b.angularFactor.y,
            dot(b.row2, axis) * b.angularFactor.z};
}

// btoclAngularScaled.
BTOCL_LANES_INLINE Vec3 angularScaled(const SetupBodies& b, Vec3 v) {
    return {dot(b.scale0, v), dot(b.scale1, v), dot(b.scale2, v)};
}

// A row's floats as btoclSolveRowOf lays them out (normal xyz and rhs, relpos1CrossNormal xyz
// and cfm, ...), a vector each, and its starting impulse.
struct RowLanes {
    Lanes f[BTOCL_SOLVE_ROW_FLOATS];
    Lanes impulse;
};
BTOCL_LANES_INLINE void rowLanesOf(RowLanes& r, const SetupBodies& A, const SetupBodies& B, Vec3 n1, Vec3 n2, Lanes rhs,
                                   Vec3 rp1, Lanes w1, Vec3 rp2, Lanes jac, Vec3 angA, Lanes wA, Vec3 angB, Lanes wB,
                                   Lanes impulse) {
    const Vec3 n = select(-n2, n1, dot(n1, n1) != 0.0f);
    const Vec3 scaledA = angularScaled(A, rp1), scaledB = angularScaled(B, rp2);
    rp1 = select(rp1, scaledA, A.scaled);
    angA = select(angA, scaledA, A.scaled);
    rp2 = select(rp2, scaledB, B.scaled);
    angB = select(angB, scaledB, B.scaled);
    // Field by field: from a list, GCC copied the row into place with `rep movsq`.
    r.f[0] = n.x, r.f[1] = n.y, r.f[2] = n.z, r.f[3] = rhs;
    r.f[4] = rp1.x, r.f[5] = rp1.y, r.f[6] = rp1.z, r.f[7] = w1;
    r.f[8] = rp2.x, r.f[9] = rp2.y, r.f[10] = rp2.z, r.f[11] = jac;
    r.f[12] = angA.x, r.f[13] = angA.y, r.f[14] = angA.z, r.f[15] = wA;
    r.f[16] = angB.x, r.f[17] = angB.y, r.f[18] = angB.z, r.f[19] = wB;
    static_assert(BTOCL_SOLVE_ROW_FLOATS == 20, "a row's fields, each set above");
    r.impulse = impulse;
}

// btoclFrictionRow along `axis` (a unit vector), no desired velocity, no slip, no anchor.
BTOCL_LANES_INLINE void frictionRowLanes(RowLanes& r, Vec3 axis, const SetupBodies& A, const SetupBodies& B,
                                         Vec3 relPos1, Vec3 relPos2, Lanes friction, const btoclSetupParams& prm) {
    const LaneMask hasA = A.rigid, hasB = B.rigid;
    const Vec3 zero = zero3();
    const Vec3 n1 = select(zero, axis, hasA);
    const Vec3 rp1 = select(zero, cross(relPos1, n1), hasA);
    const Vec3 n2 = select(zero, -axis, hasB);
    const Vec3 rp2 = select(zero, cross(relPos2, n2), hasB);
    const Vec3 angA = select(zero, angularComponent(A, rp1), hasA);
    const Vec3 angB = select(zero, angularComponent(B, rp2), hasB);
    const Lanes denom0 = select(splat(0.0f), A.invMass + dot(axis, cross(angA, relPos1)), hasA);
    const Lanes denom1 = select(splat(0.0f), B.invMass + dot(axis, cross(-angB, relPos2)), hasB);
    const Lanes jac = prm.sor / (denom0 + denom1);
    const Lanes vel1 = dot(n1, select(zero, A.linear + A.force, hasA)) + dot(rp1, select(zero, A.angular, hasA));
    const Lanes vel2 = dot(n2, select(zero, B.linear + B.force, hasB)) + dot(rp2, select(zero, B.angular, hasB));
    const Lanes velocityImpulse = (0.0f - (vel1 + vel2)) * jac;
    rowLanesOf(r, A, B, n1, n2, 0.0f + velocityImpulse, rp1, splat(0.0f), rp2, jac, angA, splat(0.0f), angB, friction,
               splat(0.0f));
}

// Eight points' rows: the normal row, one or two friction rows, and the friction directions.
struct PointRowLanes {
    RowLanes normal, friction[2];
    Vec3 dir1, dir2;
};

// The rows of the points pt[i], each between bodies A and B of its lane (two friction rows with
// `two`).
BTOCL_LANES_INLINE void pointRowLanes(PointRowLanes& out, const btoclContactPoint* const* pt, const SetupBodies& A,
                                      const SetupBodies& B, const btoclSetupParams& prm, bool two) {
    const LaneMask hasA = A.rigid, hasB = B.rigid;
    const Vec3 zero = zero3();
    const Float4Lanes onA = BTOCL_FIELD_LANES(pt, btoclContactPoint, positionOnA);
    const Float4Lanes onB = BTOCL_FIELD_LANES(pt, btoclContactPoint, positionOnB);
    const Float4Lanes normalOnB = BTOCL_FIELD_LANES(pt, btoclContactPoint, normalOnB);
    const Lanes appliedBefore = BTOCL_FIELD_LANES(pt, btoclContactPoint, impulseFriction).x;
    const Vec3 n = normalOnB.xyz();
    const Lanes distance = onA.w, friction = onB.w, restitutionCoefficient = normalOnB.w;

    // btoclContactFrameOf
    const Vec3 relPos1 = onA.xyz() - A.centerOfMass;
    const Vec3 relPos2 = onB.xyz() - B.centerOfMass;
    const Vec3 velA = select(zero, (A.linear + A.force) + cross(A.angular + A.torque, relPos1), hasA);
    const Vec3 velB = select(zero, (B.linear + B.force) + cross(B.angular + B.torque, relPos2), hasB);
    const Vec3 vel = velA - velB;
    const Lanes relVel = dot(n, vel);

    // btoclNormalRow, with the solver's cfm and erp
    const float cfm = prm.globalCfm * prm.invTimeStep;
    const Vec3 torqueAxis0 = cross(relPos1, n);
    const Vec3 torqueAxis1 = cross(relPos2, n);
    const Vec3 angA = select(zero, angularComponent(A, torqueAxis0), hasA);
    const Vec3 angB = select(zero, angularComponent(B, -torqueAxis1), hasB);
    const Lanes denom0 = select(splat(0.0f), A.invMass + dot(n, cross(angA, relPos1)), hasA);
    const Lanes denom1 = select(splat(0.0f), B.invMass + dot(n, cross(-angB, relPos2)), hasB);
    const Lanes jac = prm.sor / (denom0 + denom1 + cfm);
    const Vec3 n1 = select(zero, n, hasA), rp1 = select(zero, torqueAxis0, hasA);
    const Vec3 n2 = select(zero, -n, hasB), rp2 = select(zero, -torqueAxis1, hasB);
    const Lanes penetration = distance + prm.linearSlop;
    const Vec3 v1 = select(zero, A.linear + cross(A.angular, relPos1), hasA);
    const Vec3 v2 = select(zero, B.linear + cross(B.angular, relPos2), hasB);
    const Lanes rv = dot(n, v1 - v2);
    Lanes restitution =
        select(splat(0.0f), restitutionCoefficient * -rv, absLanes(rv) >= prm.restitutionVelocityThreshold);
    restitution = select(restitution, splat(0.0f), restitution <= 0.0f);
    const Lanes vel1Dotn =
        dot(n1, A.linear + select(zero, A.force, hasA)) + dot(rp1, A.angular + select(zero, A.torque, hasA));
    const Lanes vel2Dotn =
        dot(n2, B.linear + select(zero, B.force, hasB)) + dot(rp2, B.angular + select(zero, B.torque, hasB));
    Lanes velocityError = restitution - (vel1Dotn + vel2Dotn);
    const LaneMask penetrating = penetration > 0.0f;
    velocityError = select(velocityError, velocityError - penetration * prm.invTimeStep, penetrating);
    const Lanes positionalError = select(-penetration * prm.erp2 * prm.invTimeStep, splat(0.0f), penetrating);
    const Lanes penetrationImpulse = positionalError * jac;
    const Lanes velocityImpulse = velocityError * jac;
    const LaneMask toPush = prm.usePush ? ~(penetration > prm.pushThreshold) : LaneMask{};
    const Lanes rhs = select(penetrationImpulse + velocityImpulse, velocityImpulse, toPush);
    const Lanes rhsPenetration = select(splat(0.0f), penetrationImpulse, toPush);
    const Lanes warm =
        (prm.solverMode & BTOCL_SOLVER_USE_WARMSTARTING) ? appliedBefore * prm.warmstartingFactor : splat(0.0f);
    rowLanesOf(out.normal, A, B, n1, n2, rhs, rp1, cfm * jac, rp2, jac, angA, rhsPenetration, angB, splat(0.0f), warm);

    // btoclFrictionFrameOf, the directions chosen this step
    const Vec3 lateral = vel - n * relVel;
    const Lanes lateralSpeed2 = dot(lateral, lateral);
    const LaneMask fromVelocity = (prm.solverMode & BTOCL_SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION)
                                      ? LaneMask{}
                                      : lateralSpeed2 > FLT_EPSILON;
    const Vec3 along = lateral * (1.0f / sqrtLanes(lateralSpeed2));
    Vec3 across = BTOCL_FIELD_LANES(pt, btoclContactPoint, lateralDir2).xyz();
    if (two) {
        const Vec3 c = cross(along, n);
        across = c * (1.0f / sqrtLanes(dot(c, c)));
    }
    // btoclPlaneSpace
    const LaneMask steep = absLanes(n.z) > 0.70710678f;
    const Lanes aZ = n.y * n.y + n.z * n.z, kZ = 1.0f / sqrtLanes(aZ);
    const Lanes aX = n.x * n.x + n.y * n.y, kX = 1.0f / sqrtLanes(aX);
    const Vec3 pZ{splat(0.0f), -n.z * kZ, n.y * kZ};
    const Vec3 qZ{aZ * kZ, -n.x * pZ.z, n.x * pZ.y};
    const Vec3 pX{-n.y * kX, n.x * kX, splat(0.0f)};
    const Vec3 qX{-n.z * pX.y, n.z * pX.x, aX * kX};
    out.dir1 = select(select(pX, pZ, steep), along, fromVelocity);
    out.dir2 = select(select(qX, qZ, steep), across, fromVelocity);
    frictionRowLanes(out.friction[0], out.dir1, A, B, relPos1, relPos2, friction, prm);
    if (two) frictionRowLanes(out.friction[1], out.dir2, A, B, relPos1, relPos2, friction, prm);
}

// With `stream`, stored past the caches: the rows are written whole, so their lines need not be
// read first.
BTOCL_LANES_INLINE void storeRow(Lanes v, float* p, bool stream) {
    if (stream)
        _mm256_stream_ps(p, (__m256)v);
    else
        store(v, p);
}

// A row into its block of the lane layout (lanes not in `active` zero), its impulses with it.
BTOCL_LANES_INLINE void storeBlock(const RowLanes& r, LaneMask active, float* block, float* applied,
                                   float* pushApplied, bool stream) {
    for (int f = 0; f < BTOCL_LANE_ROW_FLOATS; ++f) {
        // Float 12 as lane_setup.h's btoclStoreLaneRow writes it: the push rhs (float 15 of the
        // solve row), else float 19.
        const Lanes value = f == BTOCL_LANE_ROW_SHARED ? select(r.f[19], r.f[15], r.f[15] != 0.0f) : r.f[f];
        storeRow(select(splat(0.0f), value, active), block + f * W, stream);
    }
    storeRow(select(splat(0.0f), r.impulse, active), applied, stream);
    storeRow(splat(0.0f), pushApplied, stream);
}

// The lanes' rows, each to its own record: four floats of a row at a time, eight rows turned
// from lanes into records by shuffles (the inverse of transpose).
BTOCL_LANES_INLINE void storeRecords(const RowLanes& r, btoclSolveRow* const* to, int count) {
    for (int v = 0; v < BTOCL_SOLVE_ROW_FLOATS / 4; ++v) {
        const __m256 x = (__m256)r.f[4 * v], y = (__m256)r.f[4 * v + 1];
        const __m256 z = (__m256)r.f[4 * v + 2], w = (__m256)r.f[4 * v + 3];
        const __m256 t0 = _mm256_unpacklo_ps(x, y), t1 = _mm256_unpackhi_ps(x, y);
        const __m256 t2 = _mm256_unpacklo_ps(z, w), t3 = _mm256_unpackhi_ps(z, w);
        const __m256 u[4] = {_mm256_shuffle_ps(t0, t2, 0x44), _mm256_shuffle_ps(t0, t2, 0xee),
                             _mm256_shuffle_ps(t1, t3, 0x44), _mm256_shuffle_ps(t1, t3, 0xee)};
        for (int i = 0; i < count; ++i) {
            const __m128 record = i < 4 ? _mm256_castps256_ps128(u[i]) : _mm256_extractf128_ps(u[i - 4], 1);
            _mm_store_ps(reinterpret_cast<float*>(to[i]) + 4 * v, record);
        }
    }
}

BTOCL_LANES_INLINE bool slotRowsInLanes(const btoclContactPoint* points, const btoclBody* bodies, const btoclLaneSlot& s,
                                        const int* ints, float* wide, float* applied, float* pushApplied,
                                        btoclFloat4* lateralDirs, const btoclSetupParams& prm, bool stream) {
    const int* numPoints = ints + BTOCL_LANE_POINTS * W;
    const int* firstPoint = ints + BTOCL_LANE_FIRST_POINT * W;
    for (int i = 0; i < W; ++i)
        for (int k = 0; k < numPoints[i]; ++k)
            if (!pointInLanes(points[firstPoint[i] + k], prm.solverMode)) return false;
    const btoclBody* sideA[W];
    const btoclBody* sideB[W];
    for (int i = 0; i < W; ++i) {
        sideA[i] = bodies + ints[BTOCL_LANE_BODY_A * W + i];
        sideB[i] = bodies + ints[BTOCL_LANE_BODY_B * W + i];
    }
    const SetupBodies A = loadSetupBodies(sideA), B = loadSetupBodies(sideB);
    const bool two = (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) != 0;
    const LaneMask pointCount = loadInts(numPoints);
    for (int k = 0; k < s.normalBlocks; ++k) {
        const LaneMask active = pointCount > k;
        const btoclContactPoint* pt[W];
        for (int i = 0; i < W; ++i) pt[i] = k < numPoints[i] ? points + firstPoint[i] + k : &kNoPoint;
        PointRowLanes rows;
        pointRowLanes(rows, pt, A, B, prm, two);
        const size_t blockFloats = BTOCL_LANE_ROW_FLOATS * W;
        const int normal = s.normalBlock + k, friction = s.frictionBlock + k * (two ? 2 : 1);
        storeBlock(rows.normal, active, wide + normal * blockFloats, applied + normal * W, pushApplied + normal * W,
                   stream);
        for (int d = 0; d < (two ? 2 : 1); ++d)
            storeBlock(rows.friction[d], active, wide + (friction + d) * blockFloats, applied + (friction + d) * W,
                       pushApplied + (friction + d) * W, stream);
        for (int i = 0; i < W; ++i) {
            if (k >= numPoints[i]) continue;
            const size_t point = size_t(firstPoint[i] + k);
            lateralDirs[2 * point] = btoclFloat4{rows.dir1.x[i], rows.dir1.y[i], rows.dir1.z[i], 0.0f};
            lateralDirs[2 * point + 1] = btoclFloat4{rows.dir2.x[i], rows.dir2.y[i], rows.dir2.z[i], 0.0f};
        }
    }
    return true;
}

// slotRowsInLanes built for AVX2 and for AVX-512VL's registers (lanesUseWideRegisters): the
// same operations, so the same bits.
BTOCL_LANES_TARGET bool slotRowsInLanesAvx2(const btoclContactPoint* points, const btoclBody* bodies,
                                            const btoclLaneSlot& s, const int* ints, float* wide, float* applied,
                                            float* pushApplied, btoclFloat4* lateralDirs, const btoclSetupParams& prm,
                                            bool stream) {
    return slotRowsInLanes(points, bodies, s, ints, wide, applied, pushApplied, lateralDirs, prm, stream);
}
BTOCL_LANES_WIDE_REGISTERS_TARGET bool slotRowsInLanesWideRegisters(const btoclContactPoint* points,
                                                                    const btoclBody* bodies, const btoclLaneSlot& s,
                                                                    const int* ints, float* wide, float* applied,
                                                                    float* pushApplied, btoclFloat4* lateralDirs,
                                                                    const btoclSetupParams& prm, bool stream) {
    return slotRowsInLanes(points, bodies, s, ints, wide, applied, pushApplied, lateralDirs, prm, stream);
}

BTOCL_LANES_TARGET bool pointRowsInLanes(StepProblem& p, size_t first, size_t count, HostSolve::RowRecords to) {
    const btoclSetupParams& prm = p.setupParams;
    for (size_t i = first; i < first + count; ++i)
        if (!pointInLanes(p.points[i], prm.solverMode)) return false;
    const btoclContactPoint* pt[W];
    const btoclBody* sideA[W];
    const btoclBody* sideB[W];
    for (int i = 0; i < W; ++i) {
        pt[i] = size_t(i) < count ? &p.points[first + size_t(i)] : &kNoPoint;
        sideA[i] = &p.bodies[size_t(pt[i]->bodyA)];
        sideB[i] = &p.bodies[size_t(pt[i]->bodyB)];
    }
    const SetupBodies A = loadSetupBodies(sideA), B = loadSetupBodies(sideB);
    const int frictionRows = p.frictionRowsPerPoint();
    PointRowLanes rows;
    pointRowLanes(rows, pt, A, B, prm, frictionRows == 2);
    const int n = int(count);
    btoclSolveRow* records[W];
    for (int i = 0; i < n; ++i) {
        const int index = int(first) + i;
        records[i] = to.rows + index;
        to.normalOfRow[index] = -1;
        to.applied[index] = rows.normal.impulse[i];
        to.pushApplied[index] = 0.0f;
        p.lateralDirs[2 * size_t(index)] = btoclFloat4{rows.dir1.x[i], rows.dir1.y[i], rows.dir1.z[i], 0.0f};
        p.lateralDirs[2 * size_t(index) + 1] = btoclFloat4{rows.dir2.x[i], rows.dir2.y[i], rows.dir2.z[i], 0.0f};
    }
    storeRecords(rows.normal, records, n);
    for (int k = 0; k < frictionRows; ++k) {
        for (int i = 0; i < n; ++i) {
            const int index = btoclFirstFrictionRow(&prm, int(first) + i) + k;
            records[i] = to.rows + index;
            to.normalOfRow[index] = int(first) + i;
            to.applied[index] = 0.0f;
            to.pushApplied[index] = 0.0f;
        }
        storeRecords(rows.friction[k], records, n);
    }
    return true;
}

}  // namespace

bool setUpSlotRowsInLanes(const btoclContactPoint* points, const btoclBody* bodies, const btoclLaneSlot& s,
                          const int* ints, float* wide, float* applied, float* pushApplied, btoclFloat4* lateralDirs,
                          const btoclSetupParams& prm, bool stream) {
    const auto setUp = lanesUseWideRegisters() ? slotRowsInLanesWideRegisters : slotRowsInLanesAvx2;
    return setUp(points, bodies, s, ints, wide, applied, pushApplied, lateralDirs, prm, stream);
}

bool setUpPointRowsInLanes(StepProblem& p, size_t first, size_t count, HostSolve& into) {
    return pointRowsInLanes(p, first, count, into.rowRecords());
}

#undef BTOCL_FIELD_LANES

}  // namespace btocl
