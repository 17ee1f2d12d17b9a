#include "InputChecks.h"

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <cmath>
#include <string>

namespace btocl {
namespace {

// Each check walks a record's fields twice at most: once summing x * 0 over all of them (0 when
// every field is finite, NaN as soon as one is not; one comparison for the common case), and
// only when that fails, once more to name the first bad field.
struct FiniteSum {
    btScalar sum = 0;
    void operator()(const char*, btScalar x) { sum += x * btScalar(0); }
    void operator()(const char*, const btVector3& v) {
        sum += v.x() * btScalar(0) + v.y() * btScalar(0) + v.z() * btScalar(0);
    }
    void operator()(const char* name, const btMatrix3x3& m) {
        for (int r = 0; r < 3; ++r) (*this)(name, m[r]);
    }
    bool allFinite() const { return sum == 0; }
};

struct FirstNonFinite {
    const char* field = nullptr;
    void operator()(const char* name, btScalar x) {
        if (!field && !std::isfinite(x)) field = name;
    }
    void operator()(const char* name, const btVector3& v) {
        for (int k = 0; k < 3; ++k) (*this)(name, v[k]);
    }
    void operator()(const char* name, const btMatrix3x3& m) {
        for (int r = 0; r < 3; ++r) (*this)(name, m[r]);
    }
};

// The name of the first non-finite field that visit(record, visitor) shows, or null.
template <class Record, class VisitFields>
const char* firstNonFinite(const Record& record, VisitFields visit) {
    FiniteSum sum;
    visit(record, sum);
    if (sum.allFinite()) return nullptr;
    FirstNonFinite first;
    visit(record, first);
    return first.field ? first.field : "a value";
}

std::string worldIndexOf(const btCollisionObject* o) { return std::to_string(o->getWorldArrayIndex()); }

[[noreturn]] void fail(const std::string& what) { throw InputError("btOpenCLConstraintSolver: " + what); }

struct BodyFields {
    template <class Visitor>
    void operator()(const btRigidBody& b, Visitor& v) const {
        v("position (its world transform's origin)", b.getWorldTransform().getOrigin());
        v("rotation (its world transform's basis)", b.getWorldTransform().getBasis());
        v("linear velocity", b.getLinearVelocity());
        v("angular velocity", b.getAngularVelocity());
        v("total force", b.getTotalForce());
        v("total torque", b.getTotalTorque());
        v("inverse mass", b.getInvMass());
        v("local inverse inertia (getInvInertiaDiagLocal)", b.getInvInertiaDiagLocal());
        v("world inverse inertia tensor (getInvInertiaTensorWorld)", b.getInvInertiaTensorWorld());
        v("linear factor", b.getLinearFactor());
        v("angular factor", b.getAngularFactor());
    }
};

// What row setup (kernels/row_setup.h) reads of a point, under the same conditions.
struct PointFields {
    int solverMode;
    template <class Visitor>
    void operator()(const btManifoldPoint& cp, Visitor& v) const {
        v("m_positionWorldOnA", cp.m_positionWorldOnA);
        v("m_positionWorldOnB", cp.m_positionWorldOnB);
        v("m_normalWorldOnB", cp.m_normalWorldOnB);
        v("distance (m_distance1)", cp.m_distance1);
        v("m_combinedFriction", cp.m_combinedFriction);
        v("m_combinedRestitution", cp.m_combinedRestitution);
        v("m_combinedRollingFriction", cp.m_combinedRollingFriction);
        v("m_combinedSpinningFriction", cp.m_combinedSpinningFriction);
        if (solverMode & SOLVER_USE_WARMSTARTING) v("m_appliedImpulse (the warm start)", cp.m_appliedImpulse);
        const int flags = cp.m_contactPointFlags;
        if (flags & (BT_CONTACT_FLAG_HAS_CONTACT_CFM | BT_CONTACT_FLAG_HAS_CONTACT_ERP)) {
            if (flags & BT_CONTACT_FLAG_HAS_CONTACT_CFM) v("m_contactCFM", cp.m_contactCFM);
            if (flags & BT_CONTACT_FLAG_HAS_CONTACT_ERP) v("m_contactERP", cp.m_contactERP);
        } else if (flags & BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) {
            v("m_combinedContactStiffness1", cp.m_combinedContactStiffness1);
            v("m_combinedContactDamping1", cp.m_combinedContactDamping1);
        }
        if ((solverMode & SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) &&
            (flags & BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED)) {
            v("m_lateralFrictionDir1 (cached)", cp.m_lateralFrictionDir1);
            v("m_lateralFrictionDir2 (cached)", cp.m_lateralFrictionDir2);
            v("m_contactMotion1", cp.m_contactMotion1);
            v("m_contactMotion2", cp.m_contactMotion2);
            v("m_frictionCFM", cp.m_frictionCFM);
        }
    }
};

// Anisotropic friction scales directions in the object's frame (HostRowSetup.cpp): its factors
// and its rotation are read even for a static object, which is not a solver body.
struct AnisotropyFields {
    template <class Visitor>
    void operator()(const btCollisionObject& o, Visitor& v) const {
        v("anisotropic friction (getAnisotropicFriction)", o.getAnisotropicFriction());
        v("rotation (its world transform's basis)", o.getWorldTransform().getBasis());
    }
};

void checkAnisotropy(const btCollisionObject* o) {
    if (!o->hasAnisotropicFriction(btCollisionObject::CF_ANISOTROPIC_FRICTION |
                                   btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION))
        return;
    if (const char* field = firstNonFinite(*o, AnisotropyFields{}))
        fail("non-finite input: the object at index " + worldIndexOf(o) + " of the world has a non-finite " + field);
}

template <class T>
void checkArray(const char* name, const char* elements, int count, T* const* array) {
    if (count < 0) fail(std::string("solveGroup: ") + name + " is " + std::to_string(count) + ", a negative count");
    if (count > 0 && !array) fail(std::string("solveGroup: ") + name + " is " + std::to_string(count) + " but its array is null");
    for (int i = 0; i < count; ++i)
        if (!array[i])
            fail(std::string("solveGroup: ") + elements + "[" + std::to_string(i) + "] is null; each of the " +
                 std::to_string(count) + " must point to an object");
}

}  // namespace

void checkSolveGroupArguments(btCollisionObject* const* bodies, int numBodies, btPersistentManifold* const* manifolds,
                              int numManifolds, btTypedConstraint* const* constraints, int numConstraints) {
    checkArray("numBodies", "bodies", numBodies, bodies);
    checkArray("numManifolds", "manifolds", numManifolds, manifolds);
    checkArray("numConstraints", "constraints", numConstraints, constraints);
}

void checkSolverInfo(const btContactSolverInfo& info) {
    if (!(info.m_timeStep > 0) || !std::isfinite(info.m_timeStep))
        fail("the solver setting m_timeStep is " + std::to_string(info.m_timeStep) + "; it must be positive and finite");
    if (info.m_numIterations < 0)
        fail("the solver setting m_numIterations is " + std::to_string(info.m_numIterations) + "; it must not be negative");
    auto finite = [](const char* field, btScalar value) {
        if (!std::isfinite(value))
            fail(std::string("non-finite input: the solver setting ") + field + " is " + std::to_string(value));
    };
    finite("m_erp2", info.m_erp2);
    finite("m_sor", info.m_sor);
    finite("m_globalCfm", info.m_globalCfm);
    finite("m_linearSlop", info.m_linearSlop);
    finite("m_restitutionVelocityThreshold", info.m_restitutionVelocityThreshold);
    finite("m_frictionERP", info.m_frictionERP);
    finite("m_leastSquaresResidualThreshold", info.m_leastSquaresResidualThreshold);
    finite("m_maxGyroscopicForce", info.m_maxGyroscopicForce);
    if (info.m_solverMode & SOLVER_USE_WARMSTARTING) finite("m_warmstartingFactor", info.m_warmstartingFactor);
    if (info.m_splitImpulse) {
        finite("m_splitImpulsePenetrationThreshold", info.m_splitImpulsePenetrationThreshold);
        finite("m_splitImpulseTurnErp", info.m_splitImpulseTurnErp);
    }
}

void checkRigidBody(const btRigidBody& body) {
    if (const char* field = firstNonFinite(body, BodyFields{}))
        fail("non-finite input: the rigid body at index " + worldIndexOf(&body) + " of the world has a non-finite " +
             field);
    // A negative mass or inertia (setMassProps takes one without a word) makes every impulse push
    // the wrong way: Bullet's solver, too, blows such a body and its neighbours up.
    const btVector3& inertia = body.getInvInertiaDiagLocal();
    const char* negative = body.getInvMass() < 0                                     ? "inverse mass (its mass)"
                           : inertia.x() < 0 || inertia.y() < 0 || inertia.z() < 0 ? "local inverse inertia (its inertia)"
                                                                                    : nullptr;
    if (negative)
        fail("the rigid body at index " + worldIndexOf(&body) + " of the world has a negative " + negative +
             "; a body's mass and inertia must not be negative");
}

void checkManifold(const btPersistentManifold& manifold, const btContactSolverInfo& info, bool anisotropic) {
    // As a joint of a body with itself (JointRows.cpp): one side's change would be lost.
    if (manifold.getBody0() == manifold.getBody1())
        fail("a contact manifold between the object at index " + worldIndexOf(manifold.getBody0()) +
             " of the world and itself has points to solve; a contact needs two objects");
    const PointFields fields{info.m_solverMode};
    const btScalar threshold = manifold.getContactProcessingThreshold();
    for (int j = 0; j < manifold.getNumContacts(); ++j) {
        const btManifoldPoint& cp = manifold.getContactPoint(j);
        if (cp.getDistance() > threshold) continue;  // not solved, as the gather skips it
        if (const char* field = firstNonFinite(cp, fields))
            fail("non-finite input: a contact point between the objects at indices " +
                 worldIndexOf(manifold.getBody0()) + " and " + worldIndexOf(manifold.getBody1()) +
                 " of the world has a non-finite " + field);
    }
    if (!anisotropic) return;  // its objects not read again (they lie scattered in memory)
    checkAnisotropy(manifold.getBody0());
    checkAnisotropy(manifold.getBody1());
}

}  // namespace btocl
