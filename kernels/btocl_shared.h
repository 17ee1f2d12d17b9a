// Structs that the host and the kernels both read. Included by OpenCL C programs (with the
// kernels' own float4/int) and by C++ (with the mirror types below): the layouts must match,
// so only 4-byte scalars and 16-byte float4s, float4s first, sizes multiples of 16.
#ifndef BTOCL_SHARED_H
#define BTOCL_SHARED_H

// On a CPU device the host asks for BTOCL_NO_CONTRACTION: no multiply-add fused, as the host's
// build fuses none, so that the device's setup and solve give the serial host reference's bits.
#if defined(__OPENCL_VERSION__) && defined(BTOCL_NO_CONTRACTION)
#pragma OPENCL FP_CONTRACT OFF
#endif

// Functions of the headers that both compile (split_grid.h, row_setup.h, ...), inlined on the
// host too: GCC's own choice left a friction row's setup a call, its records passed in memory.
#if defined(__OPENCL_VERSION__) || defined(__GNUC__)
#define BTOCL_INLINE static inline __attribute__((always_inline))
#else
#define BTOCL_INLINE static inline
#endif

// Software prefetch, on CPU devices only: the host builds the programs with
// -DBTOCL_CPU_PREFETCH there (OpenCL's own prefetch() does nothing on PoCL), and other
// compilers may not know clang's builtin.
#if defined(__OPENCL_VERSION__) && defined(BTOCL_CPU_PREFETCH) && defined(__clang__)
#define BTOCL_PREFETCHES 1
#define BTOCL_PREFETCH(p) __builtin_prefetch((__global const char*)(p))
#else
#define BTOCL_PREFETCHES 0
#define BTOCL_PREFETCH(p) ((void)0)
#endif

#ifdef __OPENCL_VERSION__
typedef float4 btoclFloat4;
#else
struct alignas(16) btoclFloat4 {
    float x, y, z, w;
};
static_assert(sizeof(int) == 4, "kernels' int is 32 bits");
#endif

// Number of sets of the 2x2 checkerboard; set index BTOCL_OVERFLOW_SET holds the overflow group
// (constraints of dynamic bodies larger than a cell), solved after the four.
#define BTOCL_NUM_SETS 4
#define BTOCL_OVERFLOW_SET 4

// Kinds of rows, in the order of their regions in gather order: [normal][friction][rolling][joint].
// A constraint's rows of each kind are contiguous (btoclConstraint::firstRow).
enum { BTOCL_ROWS_NORMAL, BTOCL_ROWS_FRICTION, BTOCL_ROWS_ROLLING, BTOCL_ROWS_JOINT, BTOCL_NUM_ROW_KINDS };

// Where each kind's region starts in gather order, by BTOCL_ROWS_*; start[BTOCL_NUM_ROW_KINDS] is
// the number of rows. Made by btoclRowRegionsOf alone: the one place that lays the regions out.
typedef struct {
    int start[BTOCL_NUM_ROW_KINDS + 1];
    int pad0, pad1, pad2;
} btoclRowRegions;

BTOCL_INLINE btoclRowRegions btoclRowRegionsOf(int numNormal, int numFriction, int numRolling, int numJoint) {
    btoclRowRegions r;
    r.start[BTOCL_ROWS_NORMAL] = 0;
    r.start[BTOCL_ROWS_FRICTION] = numNormal;
    r.start[BTOCL_ROWS_ROLLING] = numNormal + numFriction;
    r.start[BTOCL_ROWS_JOINT] = numNormal + numFriction + numRolling;
    r.start[BTOCL_NUM_ROW_KINDS] = numNormal + numFriction + numRolling + numJoint;
    r.pad0 = r.pad1 = r.pad2 = 0;
    return r;
}
BTOCL_INLINE int btoclRegionRows(const btoclRowRegions* r, int kind) { return r->start[kind + 1] - r->start[kind]; }
// The kind of the row at gather index `row`.
BTOCL_INLINE int btoclKindOfRow(const btoclRowRegions* r, int row) {
    int kind = BTOCL_ROWS_NORMAL;
    for (int k = BTOCL_ROWS_FRICTION; k < BTOCL_NUM_ROW_KINDS; ++k)
        if (row >= r->start[k]) kind = k;
    return kind;
}

// In solve order the rows lie in two regions, one per half of a velocity iteration (each pass reads
// one region front to back): every constraint's normal and joint rows, then every constraint's
// friction and rolling rows (kernels/arrange.cl).
BTOCL_INLINE int btoclInFrictionRegion(int kind) { return kind == BTOCL_ROWS_FRICTION || kind == BTOCL_ROWS_ROLLING; }
BTOCL_INLINE int btoclFrictionRegionStart(const btoclRowRegions* r) {
    return btoclRegionRows(r, BTOCL_ROWS_NORMAL) + btoclRegionRows(r, BTOCL_ROWS_JOINT);
}

// The passes of a step, each over all constraints, set after set:
// warm start: the normal rows' starting impulses applied to the bodies;
// push: the normal rows on push and turn velocities (Bullet's split impulse), once per iteration;
// normal and friction: the two halves of a velocity iteration, in SI's order of kinds: every
// constraint's joint and normal rows, then every constraint's friction and rolling rows (a
// constraint's friction right after its own normal rows let resting stacks creep: f4e01b4).
enum { BTOCL_PASS_WARMSTART, BTOCL_PASS_PUSH, BTOCL_PASS_NORMAL, BTOCL_PASS_FRICTION, BTOCL_NUM_PASSES };

// The order of a step's passes, written once here and walked by every launch mode and by the host
// reference: the warm start (when asked), the push iterations, then the velocity iterations, each
// a normal and a friction pass while iteration < numIterations and a normal pass alone past it
// (for joints that ask for more iterations than the contacts get). Made by passScheduleOf
// (bullet_plugin/step/StepPlan.h).
typedef struct {
    int warmStart;       // 1: a warm start pass first
    int pushIterations;  // 0 where no contact point may get a push share
    int numIterations;   // m_numIterations: contact rows take part in these
    int maxIterations;   // velocity iterations: numIterations, or more where a joint asks
    unsigned int orderSeed;  // with BTOCL_FLAG_RANDOM_ORDER: the step's seed of its shuffled orders
} btoclPassSchedule;

// One pass of the schedule.
typedef struct {
    int pass;           // BTOCL_PASS_*
    int iteration;      // of its push or velocity iterations, from 0
    int residual;       // its iteration's residual among the step's (push iterations first); -1: warm start
    int endsIteration;  // the last pass of its iteration: its residual is whole after it
} btoclPassStep;

BTOCL_INLINE int btoclVelocityIterationsWithFriction(btoclPassSchedule s) {
    return s.numIterations < s.maxIterations ? s.numIterations : s.maxIterations;
}
BTOCL_INLINE int btoclFirstVelocityPass(btoclPassSchedule s) { return s.warmStart + s.pushIterations; }
BTOCL_INLINE int btoclPassCount(btoclPassSchedule s) {
    const int withFriction = btoclVelocityIterationsWithFriction(s);
    return btoclFirstVelocityPass(s) + 2 * withFriction + (s.maxIterations - withFriction);
}
BTOCL_INLINE btoclPassStep btoclPassAt(btoclPassSchedule s, int index) {
    btoclPassStep p;
    p.endsIteration = 1;
    if (index < s.warmStart) {
        p.pass = BTOCL_PASS_WARMSTART;
        p.iteration = 0;
        p.residual = -1;
        p.endsIteration = 0;
        return p;
    }
    index -= s.warmStart;
    if (index < s.pushIterations) {
        p.pass = BTOCL_PASS_PUSH;
        p.iteration = index;
        p.residual = index;
        return p;
    }
    index -= s.pushIterations;
    const int withFriction = btoclVelocityIterationsWithFriction(s);
    if (index < 2 * withFriction) {
        p.iteration = index / 2;
        p.pass = (index & 1) ? BTOCL_PASS_FRICTION : BTOCL_PASS_NORMAL;
        p.endsIteration = index & 1;
    } else {
        p.iteration = index - withFriction;  // past the 2 * withFriction passes of both halves
        p.pass = BTOCL_PASS_NORMAL;
    }
    p.residual = s.pushIterations + p.iteration;
    return p;
}

// Flags of the solve kernels (SolveSettings::flags).
#define BTOCL_FLAG_APPLY_FACTORS 1   // scale applied impulses by the body factors (SI without SOLVER_SIMD)
#define BTOCL_FLAG_TRACK_RESIDUAL 2  // m_leastSquaresResidualThreshold > 0: stop early on the device
#define BTOCL_FLAG_ROTATE_POINTS 4   // each iteration starts a manifold's normal rows at another point
#define BTOCL_FLAG_RANDOM_ORDER 8    // SOLVER_RANDMIZE_ORDER: velocity passes in shuffled orders (row_solve.h)
#define BTOCL_FLAG_INTERLEAVE_FRICTION 16  // SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS: each
                                           // point's friction rows right after its normal row

// Bullet's flags that row setup reads (checked against Bullet's own values in bullet_plugin/bullet/BulletGather.cpp).
#define BTOCL_SOLVER_USE_WARMSTARTING 4
#define BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS 16
#define BTOCL_SOLVER_ENABLE_FRICTION_DIRECTION_CACHING 32
#define BTOCL_SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION 64
#define BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED 1
#define BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM 2
#define BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP 4
#define BTOCL_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING 8
#define BTOCL_CONTACT_FLAG_FRICTION_ANCHOR 16

// Slots of the control buffer that lets the device stop iterating without the host.
#define BTOCL_CONTROL_STOPPED 0         // velocity iterations converged
#define BTOCL_CONTROL_RESIDUAL 1        // max squared residual of this iteration, as float bits
#define BTOCL_CONTROL_ITERATIONS 2      // velocity iterations run
#define BTOCL_CONTROL_PUSH_STOPPED 3   // push iterations converged
#define BTOCL_CONTROL_PUSH_RESIDUAL 4
#define BTOCL_CONTROL_SIZE 8

// The progress buffer of solveStepClaimed (kernels/solve.cl), all zero before any work-group reads it, in ints:
// each work-group's count of finished groups, a cache line apart (written by its owner, read by
// the others while they wait); one squared residual per iteration (float bits), the split-
// impulse iterations first; then each work-group's claim counters, one per pass and set.
#define BTOCL_PROGRESS_LINE 16
BTOCL_INLINE int btoclRoundToLine(int n) { return (n + BTOCL_PROGRESS_LINE - 1) / BTOCL_PROGRESS_LINE * BTOCL_PROGRESS_LINE; }
BTOCL_INLINE int btoclProgressResiduals(int workGroups) { return workGroups * BTOCL_PROGRESS_LINE; }
BTOCL_INLINE int btoclProgressClaims(int workGroups, int pushIterations, int maxIterations) {
    return btoclRoundToLine(btoclProgressResiduals(workGroups) + pushIterations + maxIterations);
}
BTOCL_INLINE int btoclProgressClaimsPerGroup(int numPasses) {
    return btoclRoundToLine(numPasses * (BTOCL_OVERFLOW_SET + 1));
}
BTOCL_INLINE int btoclProgressSize(int workGroups, int numPasses, int pushIterations, int maxIterations) {
    return btoclProgressClaims(workGroups, pushIterations, maxIterations) +
           workGroups * btoclProgressClaimsPerGroup(numPasses);
}

// Scalars are packed into the w lanes of float4 fields (a record stays a whole number of 16-byte
// lines). Each lane has one name, below its record; use the names, never `.w`.

// One body as the solver sees it (btSolverBody). Static bodies: invMass 0, inertia 0.
typedef struct {
    btoclFloat4 invMass;          // xyz: inverse mass times linear factor; w: 1 if dynamic else 0
    btoclFloat4 linearFactor;     // xyz; w: the body's scalar inverse mass
    btoclFloat4 angularFactor;    // xyz; w: 1 for a rigid body (dynamic or kinematic), 0 for the fixed body
    btoclFloat4 invInertiaRow0;   // world inverse inertia tensor, rows
    btoclFloat4 invInertiaRow1;
    btoclFloat4 invInertiaRow2;
    btoclFloat4 centerOfMass;     // xyz: world position of the centre of mass
    btoclFloat4 linearVelocity;   // xyz: velocity at the start of the step (kinematic: its velocity)
    btoclFloat4 angularVelocity;  // xyz
    btoclFloat4 externalForceImpulse;   // xyz: gravity and forces times dt/mass
    btoclFloat4 externalTorqueImpulse;  // xyz
    btoclFloat4 angularScaleRow0;  // S, the world inverse inertia's square root (S S = it), rows; w
    btoclFloat4 angularScaleRow1;  // of row 0: 1 where the passes keep the body's angular velocity
    btoclFloat4 angularScaleRow2;  // change as u, dw = S u (btoclSolveRowOf), else 0
} btoclBody;
#define BTOCL_BODY_IS_DYNAMIC(b) ((b).invMass.w)        // 1 if dynamic, else 0
#define BTOCL_BODY_INV_MASS(b) ((b).linearFactor.w)     // scalar inverse mass
#define BTOCL_BODY_IS_RIGID(b) ((b).angularFactor.w)    // 1 for a rigid body, 0 for the fixed body
#define BTOCL_BODY_SCALED(b) ((b).angularScaleRow0.w)   // 1: its angular change kept scaled by S

// What a step changes of a body; written by the solve, read back by the host.
typedef struct {
    btoclFloat4 deltaLinearVelocity;
    btoclFloat4 deltaAngularVelocity;
    btoclFloat4 pushVelocity;  // push (m_splitImpulse): position correction apart from velocity
    btoclFloat4 turnVelocity;
} btoclBodyDelta;

// One constraint row (btSolverConstraint).
typedef struct {
    btoclFloat4 contactNormal1;      // xyz; w: rhs
    btoclFloat4 relpos1CrossNormal;  // xyz; w: rhsPenetration
    btoclFloat4 contactNormal2;      // xyz; w: cfm
    btoclFloat4 relpos2CrossNormal;  // xyz; w: jacDiagABInv
    btoclFloat4 angularComponentA;   // xyz; w: lowerLimit
    btoclFloat4 angularComponentB;   // xyz; w: upperLimit
    btoclFloat4 impulses;            // the four lanes named below
    int bodyA, bodyB;                // indices into the body arrays
    int frictionIndex;               // friction rows: index of their normal row
    int flags;
} btoclRow;
#define BTOCL_ROW_RHS(r) ((r).contactNormal1.w)
#define BTOCL_ROW_RHS_PENETRATION(r) ((r).relpos1CrossNormal.w)  // the push share; 0: none
#define BTOCL_ROW_CFM(r) ((r).contactNormal2.w)
#define BTOCL_ROW_JAC_DIAG_INV(r) ((r).relpos2CrossNormal.w)     // jacDiagABInv
#define BTOCL_ROW_LOWER(r) ((r).angularComponentA.w)
#define BTOCL_ROW_UPPER(r) ((r).angularComponentB.w)
#define BTOCL_ROW_APPLIED(r) ((r).impulses.x)        // appliedImpulse (host-built rows; the solve
#define BTOCL_ROW_APPLIED_PUSH(r) ((r).impulses.y)   // keeps live impulses in compact arrays)
#define BTOCL_ROW_FRICTION(r) ((r).impulses.z)       // friction coefficient of friction rows
#define BTOCL_ROW_ITERATIONS(r) ((r).flags)          // joint rows: SI's m_overrideNumSolverIterations

// A row as the iterations read it: 80 bytes (the full record's 128 less what the solve never
// reads). B's linear Jacobian is the negative of A's, as in every contact row and every row of
// Bullet's joints (JointRows.cpp refuses a joint whose rows break it); the two lanes that depend
// on the row's kind are named below. Friction and rolling rows find their normal row's impulse
// through a separate index (DeviceSolver), read only by the friction pass.
typedef struct {
    btoclFloat4 normal;              // xyz: A's linear Jacobian; w: rhs
    btoclFloat4 relpos1CrossNormal;  // xyz: A's angular Jacobian; w: cfm
    btoclFloat4 relpos2CrossNormal;  // xyz: B's angular Jacobian; w: jacDiagABInv
    btoclFloat4 angularComponentA;   // xyz; w: lower limit or rhsPenetration, by kind
    btoclFloat4 angularComponentB;   // xyz; w: upper limit or friction coefficient, by kind
} btoclSolveRow;
#define BTOCL_SOLVE_ROW_RHS(r) ((r).normal.w)
#define BTOCL_SOLVE_ROW_CFM(r) ((r).relpos1CrossNormal.w)
#define BTOCL_SOLVE_ROW_JAC_DIAG_INV(r) ((r).relpos2CrossNormal.w)
#define BTOCL_SOLVE_ROW_LOWER(r) ((r).angularComponentA.w)            // joint rows
#define BTOCL_SOLVE_ROW_UPPER(r) ((r).angularComponentB.w)            // joint rows
#define BTOCL_SOLVE_ROW_RHS_PENETRATION(r) ((r).angularComponentA.w)  // normal rows (limits 0 and 1e10)
#define BTOCL_SOLVE_ROW_FRICTION(r) ((r).angularComponentB.w)         // friction and rolling rows

// One btManifoldPoint, as the row setup kernel reads it. Its normal row has the point's index.
typedef struct {
    btoclFloat4 positionOnA;     // xyz; w: distance
    btoclFloat4 positionOnB;     // xyz; w: combined friction
    btoclFloat4 normalOnB;       // xyz; w: combined restitution
    btoclFloat4 lateralDir1;     // xyz: cached friction direction; w: contact motion 1
    btoclFloat4 lateralDir2;     // xyz; w: contact motion 2
    btoclFloat4 impulseFriction; // the four lanes named below
    btoclFloat4 contactCfmErp;   // the four lanes named below
    int bodyA, bodyB;
    int flags;                   // btManifoldPoint::m_contactPointFlags
    int firstRollingRow;         // -1, or 3 rolling/spinning rows from here
} btoclContactPoint;  // two cache lines: its friction rows are found by its index (btoclFirstFrictionRow)
#define BTOCL_POINT_DISTANCE(p) ((p).positionOnA.w)
#define BTOCL_POINT_FRICTION(p) ((p).positionOnB.w)
#define BTOCL_POINT_RESTITUTION(p) ((p).normalOnB.w)
#define BTOCL_POINT_MOTION1(p) ((p).lateralDir1.w)
#define BTOCL_POINT_MOTION2(p) ((p).lateralDir2.w)
#define BTOCL_POINT_APPLIED(p) ((p).impulseFriction.x)          // m_appliedImpulse (warm start)
#define BTOCL_POINT_ROLLING_FRICTION(p) ((p).impulseFriction.y)
#define BTOCL_POINT_SPINNING_FRICTION(p) ((p).impulseFriction.z)
#define BTOCL_POINT_FRICTION_CFM(p) ((p).impulseFriction.w)
#define BTOCL_POINT_CONTACT_CFM(p) ((p).contactCfmErp.x)
#define BTOCL_POINT_CONTACT_ERP(p) ((p).contactCfmErp.y)
#define BTOCL_POINT_STIFFNESS(p) ((p).contactCfmErp.z)
#define BTOCL_POINT_DAMPING(p) ((p).contactCfmErp.w)

// The btContactSolverInfo values that row setup reads.
typedef struct {
    float timeStep, invTimeStep, sor, globalCfm;
    float erp2, linearSlop, restitutionVelocityThreshold, warmstartingFactor;
    float pushThreshold, frictionERP;
    int usePush, solverMode;
    int numPoints, pad0, pad1, pad2;
} btoclSetupParams;

// A point's first friction row (1 or 2 rows): every point's friction rows follow the normal rows,
// in point order (StepProblem::firstFrictionRowOf).
BTOCL_INLINE int btoclFirstFrictionRow(const btoclSetupParams* prm, int point) {
    return prm->numPoints + point * ((prm->solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) ? 2 : 1);
}

// The unit of batching: the rows of one body pair (a contact manifold or a joint).
// Its rows of each kind k are contiguous: rows [firstRow[k], firstRow[k] + numRows[k]).
typedef struct {
    btoclFloat4 position;  // xyz: a point of the constraint for the global split; w: named below
    int bodyA, bodyB;      // body indices; only dynamic ones lock
    int dynamicA, dynamicB;
    int firstRow[BTOCL_NUM_ROW_KINDS];  // by BTOCL_ROWS_*
    int numRows[BTOCL_NUM_ROW_KINDS];
} btoclConstraint;
// A joint's velocity iterations: SI's m_overrideNumSolverIterations (its override, else
// m_numIterations), a whole number held as a float.
#define BTOCL_CONSTRAINT_ITERATIONS(c) ((c).position.w)

// A constraint group: one cell's constraints, ordered by batch, as a slice of the solve order.
// Batch k of the group spans solveOrder[k == 0 ? offset : batchEnd[offset + k - 1],
// batchEnd[offset + k]); batchEnd shares the group's offset since a group has at most `count` batches.
typedef struct {
    int offset;      // first position in solveOrder
    int count;       // constraints in the group
    int numBatches;
    int cell;        // linear cell index (or -1 for the overflow group)
} btoclGroup;

// The lanes layout (a CPU's vector unit; docs/architecture.md, "Lanes"). Groups of one set share
// no dynamic body, so W of them are walked side by side, one per lane: a **bundle** walks its
// groups in **slots**, each holding the next constraints of up to W groups, and the slot's rows lie in blocks
// of W rows, one per lane, each float of the W rows together (a row's BTOCL_LANE_ROW_FLOATS), so
// that a vector load reads one float of every lane's row. Rows of a
// slot's kind k lie in block first + k; a lane whose constraint has fewer rows holds zeros there.
typedef struct {
    int normalBlock;     // first block of the slot's normal rows (rows normalBlock * W + lane)
    int normalBlocks;    // the most normal rows (points) of its lanes' constraints
    int frictionBlock;   // first block of its friction rows (in the friction region, after every normal block)
    int frictionBlocks;  // normalBlocks times the friction rows per point
} btoclLaneSlot;
// A slot's lanes, as W ints each (slot s's at [s * BTOCL_LANE_INTS * W, ...)): their constraints'
// bodies, their points (normal rows; 0: an unused lane, on the fixed body) and the first of them.
enum { BTOCL_LANE_BODY_A, BTOCL_LANE_BODY_B, BTOCL_LANE_POINTS, BTOCL_LANE_FIRST_POINT, BTOCL_LANE_INTS };
// What a unit impulse does to a body (btoclSolveBody's per-unit scales), kept per body for the
// lanes: the warm start's (the factors always applied) linearPerUnit xyz, 1 for a dynamic body
// (the only ones stored), angularPerUnit xyz, 0; then the other passes' eight, the same way.
#define BTOCL_BODY_PER_UNIT_FLOATS 16
#define BTOCL_SOLVE_ROW_FLOATS 20
// A lane block's row: btoclSolveRow's floats 0 to 11 (normal and rhs, each side's angular
// Jacobian, the cfm and jacDiagABInv), then float 12 holding a normal row's push rhs
// (angularComponentA's w) or a friction row's coefficient (angularComponentB's w): a contact row
// has one of them. No angular components: the lanes take a step whose every body keeps its angular
// change scaled (BTOCL_BODY_SCALED), whose rows' components are their Jacobians (btoclSolveRowOf).
#define BTOCL_LANE_ROW_FLOATS 13
#define BTOCL_LANE_ROW_SHARED 12
// A lanes pass's part in noting which slots hold a row with a push share (few do: deep points
// alone), so that the push passes visit those alone (a slot without one changes nothing): the
// warm start notes them where push iterations follow (it reads the line of a row's push share
// anyway), else the first push pass does; the push passes after the noting skip the others.
enum { BTOCL_PUSH_SLOTS_NONE, BTOCL_PUSH_SLOTS_NOTE, BTOCL_PUSH_SLOTS_SKIP };
BTOCL_INLINE int btoclPushSlotsPart(btoclPassSchedule s, btoclPassStep p) {
    if (s.pushIterations == 0) return BTOCL_PUSH_SLOTS_NONE;
    if (p.pass == BTOCL_PASS_WARMSTART) return BTOCL_PUSH_SLOTS_NOTE;
    if (p.pass != BTOCL_PASS_PUSH) return BTOCL_PUSH_SLOTS_NONE;
    return p.iteration > 0 || s.warmStart ? BTOCL_PUSH_SLOTS_SKIP : BTOCL_PUSH_SLOTS_NOTE;
}
// Where float `field` (0 to 12, above) of wide row `index` lies.
BTOCL_INLINE int btoclWideRowFloat(int index, int field, int lanes) {
    return (index / lanes) * (BTOCL_LANE_ROW_FLOATS * lanes) + field * lanes + index % lanes;
}

#ifndef __OPENCL_VERSION__
static_assert(sizeof(btoclBody) == 14 * 16, "btoclBody layout");
static_assert(sizeof(btoclBodyDelta) == 4 * 16, "btoclBodyDelta layout");
static_assert(sizeof(btoclRow) == 8 * 16, "btoclRow layout");
static_assert(sizeof(btoclSolveRow) == 5 * 16, "btoclSolveRow layout");
static_assert(sizeof(btoclConstraint) == 16 + 12 * 4, "btoclConstraint layout");
static_assert(sizeof(btoclGroup) == 16, "btoclGroup layout");
static_assert(sizeof(btoclLaneSlot) == 16, "btoclLaneSlot layout");
static_assert(sizeof(btoclContactPoint) == 8 * 16, "btoclContactPoint layout");
static_assert(sizeof(btoclSetupParams) == 4 * 16, "btoclSetupParams layout");
static_assert(sizeof(btoclRowRegions) == 2 * 16, "btoclRowRegions layout");
#endif

#endif
