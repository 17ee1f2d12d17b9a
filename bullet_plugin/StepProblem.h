// What one step solves, gathered from Bullet: solver bodies and constraint rows, set up on the
// host exactly as btSequentialImpulseConstraintSolver sets them up (same formulas, same order
// inside each manifold), in the flat layout that the kernels read.
#pragma once

#include "SplitPlan.h"
#include "btocl_shared.h"

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
    int numNormalRows = 0, numFrictionRows = 0, numRollingRows = 0;

    // Rows set up on the host (the reference path, and the path for anisotropic friction) ...
    bool rowsOnDevice = false;
    std::vector<btoclRow> rows;
    // ... or contact points that kernels/setup.cl turns into rows (normal row i is point i).
    std::vector<btoclContactPoint> points;
    std::vector<char> pointTakesLateralDirs;  // the device computes its friction directions
    btoclSetupParams setupParams{};

    // Per normal row: its manifold point, and the index of its first friction row (-1: none).
    std::vector<btManifoldPoint*> pointOfNormalRow;
    std::vector<int> frictionRowOfNormalRow;

    // Read back after the solve: applied impulses of normal and friction rows; friction directions.
    std::vector<float> appliedImpulses;
    std::vector<btoclFloat4> lateralDirs;  // two per point, device setup only

    int numContactPoints() const { return numNormalRows; }
    int numRows() const { return numNormalRows + numFrictionRows + numRollingRows; }
};

enum class RowSetup { Device, Host };

// Builds a StepProblem from the bodies and manifolds Bullet passes in, across any number of
// solveGroup calls of one step. Throws btOpenCLSolverError on non-finite input, before any
// body or manifold is changed.
class StepProblemBuilder {
public:
    // `setup` chooses where rows are set up; the host is used anyway when an object of the step
    // has anisotropic friction, which the setup kernel does not handle.
    void begin(const btContactSolverInfo& info, RowSetup setup = RowSetup::Device);
    void addBodies(btCollisionObject* const* bodies, int numBodies);
    void addManifolds(btPersistentManifold* const* manifolds, int numManifolds);
    // Sets up (host) or packs (device) every manifold's rows and returns the finished problem.
    StepProblem& finish();
    // Returns every body's companion id to -1 (Bullet's "not in a solver").
    void releaseBodies();

    const btContactSolverInfo& info() const { return m_info; }

private:
    int solverBodyOf(btCollisionObject* object);
    int addSolverBody(btRigidBody* rb);
    void setupManifoldOnHost(btPersistentManifold* manifold);
    void packManifoldForDevice(btPersistentManifold* manifold);
    bool beginManifold(btPersistentManifold* manifold, btoclConstraint& c);
    void endManifold(btoclConstraint& c, const btVector3& pointSum);

    btContactSolverInfo m_info;
    RowSetup m_setup = RowSetup::Device;
    std::vector<btPersistentManifold*> m_manifolds;
    StepProblem m_problem;
    std::vector<btoclRow> m_normalRows, m_frictionRows, m_rollingRows;
    int m_numFriction = 0, m_numRolling = 0;  // friction and rolling rows counted so far
};

}  // namespace btocl
