#include "Quality.h"

#include <algorithm>

namespace btbench {

btScalar minContactDistance(btscenes::World& w) {
    btScalar minDistance = 0;
    btCollisionDispatcher& d = w.dispatcher();
    for (int m = 0; m < d.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = d.getManifoldByIndexInternal(m);
        for (int p = 0; p < manifold->getNumContacts(); ++p)
            minDistance = std::min(minDistance, manifold->getContactPoint(p).getDistance());
    }
    return minDistance;
}

double kineticEnergy(const btscenes::World& w) {
    double energy = 0;
    for (const btRigidBody* b : w.bodies()) {
        if (b->isStaticOrKinematicObject()) continue;
        const btVector3 v = b->getLinearVelocity(), omega = b->getAngularVelocity();
        const btScalar mass = b->getInvMass() > 0 ? 1 / b->getInvMass() : 0;
        // The inertia is diagonal in the body frame: w . I w = sum of w_local[k]^2 / invI_local[k].
        const btMatrix3x3& basis = b->getWorldTransform().getBasis();
        const btVector3 local = omega * basis;  // R^T omega
        const btVector3 invI = b->getInvInertiaDiagLocal();
        double rot = 0;
        for (int k = 0; k < 3; ++k)
            if (invI[k] > 0) rot += double(local[k]) * double(local[k]) / double(invI[k]);
        energy += 0.5 * double(mass) * double(v.length2()) + 0.5 * rot;
    }
    return energy;
}

std::vector<btVector3> dynamicPositions(const btscenes::World& w) {
    std::vector<btVector3> out;
    for (const btRigidBody* b : w.bodies())
        if (!b->isStaticOrKinematicObject()) out.push_back(b->getCenterOfMassPosition());
    return out;
}

btScalar maxDistance(const std::vector<btVector3>& a, const std::vector<btVector3>& b) {
    btScalar worst = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) worst = std::max(worst, a[i].distance(b[i]));
    return worst;
}

btScalar maxCentreHeight(const btscenes::World& w) {
    btScalar top = -BT_LARGE_FLOAT;
    for (const btRigidBody* b : w.bodies())
        if (!b->isStaticOrKinematicObject()) top = std::max(top, b->getCenterOfMassPosition().y());
    return top;
}

btScalar jointPivotGap(const btTypedConstraint& joint) {
    const btTransform& a = joint.getRigidBodyA().getCenterOfMassTransform();
    const btTransform& b = joint.getRigidBodyB().getCenterOfMassTransform();
    switch (joint.getConstraintType()) {
        case POINT2POINT_CONSTRAINT_TYPE: {
            const auto& p2p = static_cast<const btPoint2PointConstraint&>(joint);
            return (a * p2p.getPivotInA()).distance(b * p2p.getPivotInB());
        }
        case HINGE_CONSTRAINT_TYPE: {
            const auto& hinge = static_cast<const btHingeConstraint&>(joint);
            return (a * hinge.getAFrame().getOrigin()).distance(b * hinge.getBFrame().getOrigin());
        }
        case CONETWIST_CONSTRAINT_TYPE: {
            const auto& cone = static_cast<const btConeTwistConstraint&>(joint);
            return (a * cone.getAFrame().getOrigin()).distance(b * cone.getBFrame().getOrigin());
        }
        case FIXED_CONSTRAINT_TYPE: {
            const auto& fixed = static_cast<const btFixedConstraint&>(joint);
            return (a * fixed.getFrameOffsetA().getOrigin()).distance(b * fixed.getFrameOffsetB().getOrigin());
        }
        default:
            return -1;
    }
}

btScalar maxJointError(const btscenes::World& w) {
    btScalar worst = -1;
    for (const btTypedConstraint* j : w.constraints())
        if (j->isEnabled()) worst = std::max(worst, jointPivotGap(*j));
    return worst;
}

}  // namespace btbench
