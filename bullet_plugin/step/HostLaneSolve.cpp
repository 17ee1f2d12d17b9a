#include "HostLaneSolve.h"

#include "HostParallel.h"
#include "lane_setup.h"
#include "row_solve.h"

#include <algorithm>
#include <cfloat>
#include <cstddef>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

// The solve's functions are built for AVX2 (eight float lanes, a blend a select) whatever the
// build's target, and called only where the CPU has it (HostLaneSolve::available): each has the
// target attribute, and none has external linkage, so no other code is built for AVX2.
#if defined(__x86_64__) && defined(__GNUC__)
#define BTOCL_LANES_TARGET __attribute__((target("avx2")))
#define BTOCL_HAS_HOST_LANES 1
#else
#define BTOCL_LANES_TARGET
#define BTOCL_HAS_HOST_LANES 0
#endif
// The row functions inlined into the pass, where the slot's bodies stay in registers.
#define BTOCL_LANES_INLINE BTOCL_LANES_TARGET inline __attribute__((always_inline))

namespace btocl {
namespace {

constexpr int W = HostLaneSolve::kLanes;
typedef float Lanes __attribute__((vector_size(4 * W)));
typedef int LaneMask __attribute__((vector_size(4 * W)));

BTOCL_LANES_INLINE Lanes load(const float* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
BTOCL_LANES_INLINE LaneMask loadInts(const int* p) {
    LaneMask v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
BTOCL_LANES_INLINE void store(Lanes v, float* p) { std::memcpy(p, &v, sizeof v); }
// OpenCL's select(a, b, m): b where m is set, else a.
BTOCL_LANES_INLINE Lanes select(Lanes a, Lanes b, LaneMask m) { return m ? b : a; }
BTOCL_LANES_INLINE Lanes splat(float x) { return Lanes{} + x; }

// A side's bodies of a slot's lanes, one vector per float (lane_solve.h, btoclLaneBodies).
struct LaneBodies {
    Lanes lpuX, lpuY, lpuZ, apuX, apuY, apuZ;
    Lanes linX, linY, linZ, angX, angY, angZ;
    Lanes dynamic;
};

const float* perUnitOf(const std::vector<float>& perUnit, int slot, int side, int warmStart) {
    return perUnit.data() + ((2 * slot + side) * 2 + (warmStart ? 0 : 1)) * (BTOCL_LANE_PER_UNIT_FLOATS * W);
}

BTOCL_LANES_INLINE LaneBodies loadBodies(const btoclBodyDelta* deltas, const float* perUnit, const int* body,
                                         int push) {
    LaneBodies l;
    const int offset = push ? 8 : 0;
    for (int i = 0; i < W; ++i) {
        const float* d = reinterpret_cast<const float*>(deltas + body[i]) + offset;
        l.linX[i] = d[0];
        l.linY[i] = d[1];
        l.linZ[i] = d[2];
        l.angX[i] = d[4];
        l.angY[i] = d[5];
        l.angZ[i] = d[6];
    }
    l.lpuX = load(perUnit);
    l.lpuY = load(perUnit + W);
    l.lpuZ = load(perUnit + 2 * W);
    l.dynamic = load(perUnit + 3 * W);
    l.apuX = load(perUnit + 4 * W);
    l.apuY = load(perUnit + 5 * W);
    l.apuZ = load(perUnit + 6 * W);
    return l;
}

// Each dynamic lane's velocities back (others never change); lanes of a slot share no dynamic body.
BTOCL_LANES_INLINE void storeBodies(btoclBodyDelta* deltas, const int* body, int push, const LaneBodies& l) {
    const int offset = push ? 8 : 0;
    for (int i = 0; i < W; ++i) {
        if (l.dynamic[i] == 0.0f) continue;
        float* d = reinterpret_cast<float*>(deltas + body[i]) + offset;
        d[0] = l.linX[i];
        d[1] = l.linY[i];
        d[2] = l.linZ[i];
        d[4] = l.angX[i];
        d[5] = l.angY[i];
        d[6] = l.angZ[i];
    }
}

#define ROW_FIELD(f) load(row + (f) * W)

BTOCL_LANES_INLINE void applyImpulse(const float* row, LaneBodies& A, LaneBodies& B, Lanes impulse, LaneMask active) {
    const Lanes nX = ROW_FIELD(0), nY = ROW_FIELD(1), nZ = ROW_FIELD(2);
    A.linX = select(A.linX, A.linX + (nX * A.lpuX) * impulse, active);
    A.linY = select(A.linY, A.linY + (nY * A.lpuY) * impulse, active);
    A.linZ = select(A.linZ, A.linZ + (nZ * A.lpuZ) * impulse, active);
    A.angX = select(A.angX, A.angX + (ROW_FIELD(12) * A.apuX) * impulse, active);
    A.angY = select(A.angY, A.angY + (ROW_FIELD(13) * A.apuY) * impulse, active);
    A.angZ = select(A.angZ, A.angZ + (ROW_FIELD(14) * A.apuZ) * impulse, active);
    B.linX = select(B.linX, B.linX - (nX * B.lpuX) * impulse, active);
    B.linY = select(B.linY, B.linY - (nY * B.lpuY) * impulse, active);
    B.linZ = select(B.linZ, B.linZ - (nZ * B.lpuZ) * impulse, active);
    B.angX = select(B.angX, B.angX + (ROW_FIELD(16) * B.apuX) * impulse, active);
    B.angY = select(B.angY, B.angY + (ROW_FIELD(17) * B.apuY) * impulse, active);
    B.angZ = select(B.angZ, B.angZ + (ROW_FIELD(18) * B.apuZ) * impulse, active);
}

BTOCL_LANES_INLINE void solveRows(const float* row, float* applied, LaneBodies& A, LaneBodies& B, Lanes lower,
                                  Lanes upper, int push, LaneMask active) {
    const Lanes nX = ROW_FIELD(0), nY = ROW_FIELD(1), nZ = ROW_FIELD(2);
    const Lanes old = load(applied);
    const Lanes start = (push ? ROW_FIELD(15) : ROW_FIELD(3)) - old * ROW_FIELD(7);
    const Lanes vX = (nX * A.linX - nX * B.linX) + (ROW_FIELD(4) * A.angX + ROW_FIELD(8) * B.angX);
    const Lanes vY = (nY * A.linY - nY * B.linY) + (ROW_FIELD(5) * A.angY + ROW_FIELD(9) * B.angY);
    const Lanes vZ = (nZ * A.linZ - nZ * B.linZ) + (ROW_FIELD(6) * A.angZ + ROW_FIELD(10) * B.angZ);
    const Lanes unclamped = start - (vX + vY + vZ) * ROW_FIELD(11);
    const Lanes sum = old + unclamped;
    const LaneMask below = sum < lower, above = sum > upper;
    const Lanes delta = select(select(unclamped, upper - old, above), lower - old, below);
    const Lanes next = select(select(sum, upper, above), lower, below);
    store(select(old, next, active), applied);
    applyImpulse(row, A, B, delta, active);
}

#undef ROW_FIELD

// The row setup of lane_setup.h (row_setup.h's contact rows) eight points at a time, a point a
// lane, for the points it takes (pointInLanes): the same operations in the same order in each
// lane, so the same bits as the scalar setup.
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
    Vec3 xyz() const { return {x, y, z}; }
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
    Vec3 centerOfMass, linear, angular, force, torque, row0, row1, row2, angularFactor;
    Lanes invMass;
    LaneMask rigid;
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
    return s;
}

// btoclAngularComponent.
BTOCL_LANES_INLINE Vec3 angularComponent(const SetupBodies& b, Vec3 axis) {
    return {dot(b.row0, axis) * b.angularFactor.x, dot(b.row1, axis) * b.angularFactor.y,
            dot(b.row2, axis) * b.angularFactor.z};
}

// A row in its block's lanes (btoclSolveRowOf's floats; lanes not in `active` zero), its
// starting impulse with it.
BTOCL_LANES_INLINE void storeRowLanes(float* block, float* applied, float* pushApplied, LaneMask active, Vec3 n1,
                                      Vec3 n2, Lanes rhs, Vec3 rp1, Lanes w1, Vec3 rp2, Lanes jac, Vec3 angA,
                                      Lanes wA, Vec3 angB, Lanes wB, Lanes impulse) {
    const Vec3 n = select(-n2, n1, dot(n1, n1) != 0.0f);
    const Lanes fields[BTOCL_SOLVE_ROW_FLOATS] = {n.x,    n.y,    n.z,    rhs,    rp1.x,  rp1.y, rp1.z,
                                                  w1,     rp2.x,  rp2.y,  rp2.z,  jac,    angA.x, angA.y,
                                                  angA.z, wA,     angB.x, angB.y, angB.z, wB};
    for (int f = 0; f < BTOCL_SOLVE_ROW_FLOATS; ++f) store(select(splat(0.0f), fields[f], active), block + f * W);
    store(select(splat(0.0f), impulse, active), applied);
    store(splat(0.0f), pushApplied);
}

// btoclFrictionRow along `axis` (a unit vector), no desired velocity, no slip, no anchor.
BTOCL_LANES_INLINE void frictionRowLanes(Vec3 axis, const SetupBodies& A, const SetupBodies& B, LaneMask hasA,
                                         LaneMask hasB, Vec3 relPos1, Vec3 relPos2, Lanes friction,
                                         const btoclSetupParams& prm, LaneMask active, float* block,
                                         float* applied, float* pushApplied) {
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
    storeRowLanes(block, applied, pushApplied, active, n1, n2, 0.0f + velocityImpulse, rp1, splat(0.0f), rp2, jac,
                  angA, splat(0.0f), angB, friction, splat(0.0f));
}

// Whether the lanes' setup takes a point: a contact with the solver's own cfm and erp, no
// friction anchor, its friction directions chosen this step. The others are set up one lane at a
// time (btoclSetupLaneRows).
bool pointInLanes(const btoclContactPoint& pt, int solverMode) {
    const int own = BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM | BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP |
                    BTOCL_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING | BTOCL_CONTACT_FLAG_FRICTION_ANCHOR;
    const bool cached = (solverMode & BTOCL_SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) &&
                        (pt.flags & BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED);
    return (pt.flags & own) == 0 && !cached;
}

// The rows of one slot, eight lanes at a time, where every point of the slot is one the lanes
// take; returns false (nothing written) otherwise.
BTOCL_LANES_TARGET bool setUpSlotRowsInLanes(const btoclContactPoint* points, const btoclBody* bodies,
                                             const btoclLaneSlot& s, const int* ints, float* wide, float* applied,
                                             float* pushApplied, btoclFloat4* lateralDirs,
                                             const btoclSetupParams& prm) {
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
    const LaneMask hasA = A.rigid, hasB = B.rigid;
    const Vec3 zero = zero3();
    const bool two = (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) != 0;
    const LaneMask pointCount = loadInts(numPoints);
    // A lane past its points reads this one (its rows are stored as zeros).
    alignas(16) static const btoclContactPoint kNoPoint{};
    const float cfm = prm.globalCfm * prm.invTimeStep;
    for (int k = 0; k < s.normalBlocks; ++k) {
        const LaneMask active = pointCount > k;
        const btoclContactPoint* pt[W];
        for (int i = 0; i < W; ++i) pt[i] = k < numPoints[i] ? points + firstPoint[i] + k : &kNoPoint;
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

        // btoclNormalRow
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
        Lanes restitution = select(splat(0.0f), restitutionCoefficient * -rv, absLanes(rv) >= prm.restitutionVelocityThreshold);
        restitution = select(restitution, splat(0.0f), restitution <= 0.0f);
        const Lanes vel1Dotn = dot(n1, A.linear + select(zero, A.force, hasA)) + dot(rp1, A.angular + select(zero, A.torque, hasA));
        const Lanes vel2Dotn = dot(n2, B.linear + select(zero, B.force, hasB)) + dot(rp2, B.angular + select(zero, B.torque, hasB));
        Lanes velocityError = restitution - (vel1Dotn + vel2Dotn);
        const LaneMask penetrating = penetration > 0.0f;
        velocityError = select(velocityError, velocityError - penetration * prm.invTimeStep, penetrating);
        const Lanes positionalError = select(-penetration * prm.erp2 * prm.invTimeStep, splat(0.0f), penetrating);
        const Lanes penetrationImpulse = positionalError * jac;
        const Lanes velocityImpulse = velocityError * jac;
        const LaneMask toPush = prm.usePush ? ~(penetration > prm.pushThreshold) : LaneMask{};
        const Lanes rhs = select(penetrationImpulse + velocityImpulse, velocityImpulse, toPush);
        const Lanes rhsPenetration = select(splat(0.0f), penetrationImpulse, toPush);
        const Lanes warm = (prm.solverMode & BTOCL_SOLVER_USE_WARMSTARTING) ? appliedBefore * prm.warmstartingFactor
                                                                           : splat(0.0f);
        const int block = s.normalBlock + k;
        storeRowLanes(wide + size_t(block) * BTOCL_SOLVE_ROW_FLOATS * W, applied + size_t(block) * W,
                      pushApplied + size_t(block) * W, active, n1, n2, rhs, rp1, cfm * jac, rp2, jac, angA,
                      rhsPenetration, angB, splat(0.0f), warm);

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
        const Vec3 dir1 = select(select(pX, pZ, steep), along, fromVelocity);
        const Vec3 dir2 = select(select(qX, qZ, steep), across, fromVelocity);
        for (int i = 0; i < W; ++i) {
            if (k >= numPoints[i]) continue;
            const size_t point = size_t(firstPoint[i] + k);
            lateralDirs[2 * point] = btoclFloat4{dir1.x[i], dir1.y[i], dir1.z[i], 0.0f};
            lateralDirs[2 * point + 1] = btoclFloat4{dir2.x[i], dir2.y[i], dir2.z[i], 0.0f};
        }
        const int frictionBlock = s.frictionBlock + k * (two ? 2 : 1);
        frictionRowLanes(dir1, A, B, hasA, hasB, relPos1, relPos2, friction, prm, active,
                         wide + size_t(frictionBlock) * BTOCL_SOLVE_ROW_FLOATS * W, applied + size_t(frictionBlock) * W,
                         pushApplied + size_t(frictionBlock) * W);
        if (two)
            frictionRowLanes(dir2, A, B, hasA, hasB, relPos1, relPos2, friction, prm, active,
                             wide + size_t(frictionBlock + 1) * BTOCL_SOLVE_ROW_FLOATS * W,
                             applied + size_t(frictionBlock + 1) * W, pushApplied + size_t(frictionBlock + 1) * W);
    }
    return true;
}

#undef BTOCL_FIELD_LANES

}  // namespace

// Slot after slot as setup.cl's setupLaneSlots sets them up (lane_setup.h): the same bits.
void HostLaneSolve::setUp(StepProblem& p, const BatchLayout& split, int flags) {
    layOutLanes(split, p.constraints.data(), p.regions, W, p.frictionRowsPerPoint(), 1, m_layout);
    const size_t numSlots = m_layout.slots.size();
    m_rows.resize(size_t(m_layout.numBlocks) * BTOCL_SOLVE_ROW_FLOATS * W);
    m_applied.resize(size_t(m_layout.numBlocks) * W);
    m_pushApplied.resize(size_t(m_layout.numBlocks) * W);
    m_perUnit.resize(numSlots * 4 * BTOCL_LANE_PER_UNIT_FLOATS * W);
    m_inVectors.resize(numSlots);
    p.lateralDirs.resize(2 * p.points.size());
    parallelFor(numSlots, [&](size_t slot) {
        const int* ints = m_layout.laneInts.data() + slot * (BTOCL_LANE_INTS * W);
        btoclSetupLanePerUnit(p.bodies.data(), p.deltas.data(), ints, int(slot), m_perUnit.data(), flags, W);
        m_inVectors[slot] = setUpSlotRowsInLanes(p.points.data(), p.bodies.data(), m_layout.slots[slot], ints,
                                                 m_rows.data(), m_applied.data(), m_pushApplied.data(),
                                                 p.lateralDirs.data(), p.setupParams);
        if (m_inVectors[slot]) return;
        for (int lane = 0; lane < W; ++lane)
            btoclSetupLaneRows(p.points.data(), p.bodies.data(), m_layout.slots[slot], ints, lane, m_rows.data(),
                               m_applied.data(), m_pushApplied.data(), p.lateralDirs.data(), &p.setupParams, W);
    }, W * kContactConstraintWeight);
}

namespace {

// lane_solve.h's btoclSolveLaneSlot, for every slot of every bundle, set after set.
BTOCL_LANES_TARGET void solveLanePass(const LaneLayout& layout, const std::vector<float>& rows,
                                      std::vector<float>& applied, std::vector<float>& pushApplied,
                                      const std::vector<float>& perUnit, btoclBodyDelta* deltas, int pass) {
    const int push = pass == BTOCL_PASS_PUSH, warmStart = pass == BTOCL_PASS_WARMSTART;
    const int perPoint = layout.frictionPerPoint;
    const int blockFloats = BTOCL_SOLVE_ROW_FLOATS * W;
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set)
        for (int bi = layout.setBundleStart[size_t(set)]; bi < layout.setBundleStart[size_t(set) + 1]; ++bi) {
            const btoclGroup& bundle = layout.bundles[size_t(bi)];
            for (int slot = bundle.offset; slot < bundle.offset + bundle.count; ++slot) {
                const btoclLaneSlot& s = layout.slots[size_t(slot)];
                const int* ints = layout.laneInts.data() + size_t(slot) * (BTOCL_LANE_INTS * W);
                const int* bodyA = ints + BTOCL_LANE_BODY_A * W;
                const int* bodyB = ints + BTOCL_LANE_BODY_B * W;
                const LaneMask numPoints = loadInts(ints + BTOCL_LANE_POINTS * W);
                LaneBodies A = loadBodies(deltas, perUnitOf(perUnit, slot, 0, warmStart), bodyA, push);
                LaneBodies B = loadBodies(deltas, perUnitOf(perUnit, slot, 1, warmStart), bodyB, push);
                if (pass == BTOCL_PASS_FRICTION) {
                    for (int k = 0; k < s.frictionBlocks; ++k) {
                        const int block = s.frictionBlock + k;
                        const float* row = rows.data() + size_t(block) * blockFloats;
                        const Lanes total = load(applied.data() + size_t(s.normalBlock + k / perPoint) * W);
                        const Lanes limit = load(row + 19 * W) * total;
                        const LaneMask active = (numPoints * perPoint > k) & (total > 0.0f);
                        solveRows(row, applied.data() + size_t(block) * W, A, B, -limit, limit, 0, active);
                    }
                } else {
                    for (int k = 0; k < s.normalBlocks; ++k) {
                        const int block = s.normalBlock + k;
                        const float* row = rows.data() + size_t(block) * blockFloats;
                        LaneMask active = numPoints > k;
                        if (warmStart) {
                            applyImpulse(row, A, B, load(applied.data() + size_t(block) * W), active);
                        } else if (push) {
                            active &= load(row + 15 * W) != 0.0f;  // no push share: skipped
                            solveRows(row, pushApplied.data() + size_t(block) * W, A, B, splat(0.0f),
                                      splat(BTOCL_FLT_MAX), 1, active);
                        } else {
                            solveRows(row, applied.data() + size_t(block) * W, A, B, splat(0.0f),
                                      splat(BTOCL_FLT_MAX), 0, active);
                        }
                    }
                }
                storeBodies(deltas, bodyA, push, A);
                storeBodies(deltas, bodyB, push, B);
            }
        }
}

}  // namespace

size_t HostLaneSolve::slotsInVectors() const {
    return size_t(std::count(m_inVectors.begin(), m_inVectors.end(), 1));
}

bool HostLaneSolve::available() {
#if BTOCL_HAS_HOST_LANES
    return __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}

int HostLaneSolve::solve(StepProblem& p, const btoclPassSchedule& passes) {
    const int numPasses = p.constraints.empty() ? 0 : btoclPassCount(passes);
    int iterations = 0;
    for (int i = 0; i < numPasses; ++i) {
        const btoclPassStep step = btoclPassAt(passes, i);
        solveLanePass(m_layout, m_rows, m_applied, m_pushApplied, m_perUnit, p.deltas.data(), step.pass);
        if (step.endsIteration && step.pass != BTOCL_PASS_PUSH) ++iterations;
    }
    // Every row's impulse back in gather order, as the write-back reads them.
    const std::vector<int>& rowMap = m_layout.rowMap;
    p.appliedImpulses.resize(rowMap.size());
    for (size_t r = 0; r < rowMap.size(); ++r) p.appliedImpulses[r] = m_applied[size_t(rowMap[r])];
    return iterations;
}

}  // namespace btocl
