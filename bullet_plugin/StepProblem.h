// What one step solves, gathered from Bullet: solver bodies and constraint rows, set up on the
// host exactly as btSequentialImpulseConstraintSolver sets them up (same formulas, same order
// inside each manifold), in the flat layout that the kernels read.
#pragma once

#include "ConstraintBatches.h"
#include "btOclShared.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>
#include <LinearMath/btTransform.h>

#include <vector>

class btCollisionObject;
class btPersistentManifold;
class btRigidBody;
class btManifoldPoint;

namespace btocl {

struct StepProblem {
    // Per solver body. Index 0 is the fixed body that every static object maps to (as SI's).
    std::vector<btRigidBody*> original;      // null for the fixed body
    std::vector<btoclBody> bodies;
    std::vector<btoclBodyDelta> deltas;      // start values: the warm-start impulses applied
    std::vector<btTransform> worldTransforms;
    std::vector<SplitBody> splitBodies;

    // One constraint per manifold that has rows; rows laid out [normal][friction][rolling].
    std::vector<btoclConstraint> constraints;
    std::vector<btoclRow> rows;
    int numNormalRows = 0, numFrictionRows = 0, numRollingRows = 0;

    // Per normal row: its manifold point, and the index in `rows` of its first friction row (-1: none).
    std::vector<btManifoldPoint*> pointOfNormalRow;
    std::vector<int> frictionRowOfNormalRow;

    int numContactPoints() const { return numNormalRows; }
    int numRows() const { return int(rows.size()); }
};

// Builds a StepProblem from the bodies and manifolds Bullet passes in, across any number of
// solveGroup calls of one step. Throws btOpenCLSolverError on non-finite input, before any
// body or manifold is changed.
class StepProblemBuilder {
public:
    void begin(const btContactSolverInfo& info);
    void addBodies(btCollisionObject* const* bodies, int numBodies);
    void addManifolds(btPersistentManifold* const* manifolds, int numManifolds);
    // Lays the rows out flat and returns the finished problem.
    StepProblem& finish();
    // Returns every body's companion id to -1 (Bullet's "not in a solver").
    void releaseBodies();

    const btContactSolverInfo& info() const { return m_info; }

private:
    struct SetupBody;
    int solverBodyOf(btCollisionObject* object);
    int addSolverBody(btRigidBody* rb);
    void addManifold(btPersistentManifold* manifold);

    btContactSolverInfo m_info;
    StepProblem m_problem;
    std::vector<btoclRow> m_normalRows, m_frictionRows, m_rollingRows;
    std::vector<int> m_frictionOfNormal;  // local friction index per normal row
};

}  // namespace btocl
