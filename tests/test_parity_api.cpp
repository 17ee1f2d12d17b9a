// What a user of btOpenCLConstraintSolver sees beside the physics: a clear error for joints
// (they come in a later issue), plausible statistics, a device name. These always run our
// solver (BTOCL_PARITY_REFERENCE_ONLY does not apply: there is no SI counterpart).
#include "TestWorld.h"

#include <cctype>

using namespace testworld;

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool finiteState(const btRigidBody* b) {
    const btVector3 p = pos(b), v = b->getLinearVelocity(), w = b->getAngularVelocity();
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(p[k]) || !std::isfinite(v[k]) || !std::isfinite(w[k])) return false;
    return true;
}

}  // namespace

TEST_CASE("parity: a world with a joint gets a btOpenCLSolverError that names joints", "[parity]") {
    World w(SolverKind::OpenCL);
    w.addGround();
    btRigidBody* a = w.addUnitBox(btVector3(0, 3, 0));
    btRigidBody* b = w.addUnitBox(btVector3(1, 3, 0));
    btPoint2PointConstraint* joint = w.addConstraint(std::make_unique<btPoint2PointConstraint>(
        *a, *b, btVector3(btScalar(0.5), 0, 0), btVector3(btScalar(-0.5), 0, 0)));
    std::string message;
    try {
        w.step();
        FAIL("stepping a world with a btTypedConstraint should throw btOpenCLSolverError");
    } catch (const btOpenCLSolverError& e) {
        message = e.what();
    }
    INFO("message: " << message);
    REQUIRE(lower(message).find("joint") != std::string::npos);
    // The error leaves the world usable: without the joint, stepping works and stays finite.
    w.dyn().removeConstraint(joint);
    for (int i = 0; i < 30; ++i) w.step();
    REQUIRE(finiteState(a));
    REQUIRE(finiteState(b));
    REQUIRE(pos(a).y() < 3);  // it fell
}

TEST_CASE("parity: getLastStats counts the bodies and contact points of a known scene", "[parity]") {
    World w(SolverKind::OpenCL);
    w.addGround();
    for (int i = 0; i < 3; ++i) w.addUnitBox(btVector3(btScalar(3 * i), btScalar(0.5), 0));
    for (int i = 0; i < 10; ++i) w.step();
    const btOpenCLSolverStats& s = w.openCL()->getLastStats();
    CAPTURE(s.numBodies, s.numContactPoints, s.numJointRows, s.numConstraintRows, s.numCellGroups,
            s.numBatchesMax, s.numBatchesMean, s.msTotal);
    // A box resting flat on a box gets 4 points (btBoxBoxDetector clips the faces).
    REQUIRE(w.numContactPoints() == 12);
    REQUIRE(s.numContactPoints == w.numContactPoints());
    // Three dynamic boxes, plus the ground if the solver counts static bodies it touches.
    REQUIRE(s.numBodies >= 3);
    REQUIRE(s.numBodies <= 4);
    REQUIRE(s.numJointRows == 0);
    // Each point has a normal row and (friction > 0) at least one friction row.
    REQUIRE(s.numConstraintRows >= 2 * s.numContactPoints);
    REQUIRE(s.numCellGroups >= 1);
    // Some group has a batch (the 4 points of a box may fall into different cells, so no more).
    REQUIRE(s.numBatchesMax >= 1);
    REQUIRE(s.validationFailures == 0);
    REQUIRE(s.msTotal > 0);
}

TEST_CASE("parity: getDeviceName names the device", "[parity]") {
    btOpenCLConstraintSolver solver(validatingConfig());
    REQUIRE_FALSE(solver.getDeviceName().empty());
}
