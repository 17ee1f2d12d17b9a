// Scenes with joints (btTypedConstraint), as free functions on a World (TestWorld.h), like
// Scenes.h. Bodies and joints are made in a fixed order, so two builds match body for body and
// joint for joint. Everything hangs or floats in the air unless said otherwise: no contacts.
#pragma once

#include "TestWorld.h"

#include <string>
#include <vector>

namespace testworld {

// A 1 kg sphere of radius 0.2 on a massless rod of `length` from the fixed point `pivot`,
// started `angle` radians from the vertical in the x-y plane.
inline btRigidBody* addPendulum(World& w, const btVector3& pivot, btScalar length, btScalar angle) {
    const btVector3 bob = pivot + btVector3(btSin(angle), -btCos(angle), 0) * length;
    btRigidBody* b = w.addSphere(btScalar(0.2), 1, at(bob));
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*b, pivot - bob));
    return b;
}

// `links` boxes of 0.2 x 0.5 x 0.2 m, 1 kg, hanging from `top` (a fixed point) in a vertical line,
// each joined to the next at their touching faces by a point-to-point joint; the lowest starts
// `kick` m/s sideways. Returns the links, top first.
inline std::vector<btRigidBody*> addChain(World& w, const btVector3& top, int links, btScalar kick = 0) {
    const btVector3 half(btScalar(0.1), btScalar(0.25), btScalar(0.1));
    std::vector<btRigidBody*> chain;
    for (int i = 0; i < links; ++i) {
        BodyOptions o;
        if (i == links - 1) o.linearVelocity = btVector3(kick, 0, 0);
        chain.push_back(w.addBox(half, 1, at(top - btVector3(0, btScalar(0.25) + btScalar(0.5) * btScalar(i), 0)), o));
    }
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*chain[0], btVector3(0, btScalar(0.25), 0)));
    for (int i = 1; i < links; ++i)
        w.addConstraint(std::make_unique<btPoint2PointConstraint>(*chain[size_t(i) - 1], *chain[size_t(i)],
                                                                  btVector3(0, btScalar(-0.25), 0),
                                                                  btVector3(0, btScalar(0.25), 0)));
    return chain;
}

// Every joint type btDiscreteDynamicsWorld accepts (point-to-point, hinge, hinge2, universal,
// slider, cone-twist, generic 6-DoF, 6-DoF spring and spring2, fixed, gear), to the fixed body, to
// a static body and between two dynamic bodies, with limits and motors where the type has them;
// some with a breaking threshold, a feedback, an iteration override, their own ERP/CFM; one
// disabled, one to a kinematic body. Bodies start moving so that the joints have errors to
// correct. Returns each joint's name, in the world's joint order.
inline std::vector<std::string> addJointZoo(World& w) {
    std::vector<std::string> names;
    int slot = 0;
    // Each joint gets its own spot in the air, 4 m apart, so nothing touches anything.
    auto spot = [&]() { const int k = slot++; return btVector3(btScalar(k % 6) * 4, 20 + btScalar(k / 6) * 4, 0); };
    const btVector3 half(btScalar(0.3), btScalar(0.2), btScalar(0.25));
    auto box = [&](const btVector3& p, const btVector3& v = btVector3(0, 0, 0), const btVector3& wv = btVector3(0, 0, 0)) {
        BodyOptions o;
        o.linearVelocity = v;
        o.angularVelocity = wv;
        return w.addBox(half, btScalar(1.5), at(p, btQuaternion(btVector3(1, 2, 3).normalized(), btScalar(0.3))), o);
    };
    auto staticBeam = [&](const btVector3& p) { return w.addBox(btVector3(1, btScalar(0.1), btScalar(0.1)), 0, at(p)); };
    auto add = [&](std::unique_ptr<btTypedConstraint> c, const char* name) {
        btTypedConstraint* raw = w.addConstraint(std::move(c));
        names.push_back(name);
        return raw;
    };
    const btVector3 spin(btScalar(0.7), btScalar(-0.4), btScalar(1.1)), drift(btScalar(0.5), btScalar(0.3), btScalar(-0.4));
    const btTransform frameA(btQuaternion(btVector3(0, 1, 0), btScalar(0.2)), btVector3(btScalar(0.5), 0, 0));
    const btTransform frameB(btQuaternion(btVector3(0, 0, 1), btScalar(-0.1)), btVector3(btScalar(-0.5), 0, 0));
    const btVector3 apart(1, 0, 0);

    {  // point-to-point to the fixed body, with an impulse clamp and its own damping
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btPoint2PointConstraint>(*a, btVector3(btScalar(0.4), btScalar(0.3), 0));
        c->m_setting.m_impulseClamp = 3;
        c->m_setting.m_damping = btScalar(0.8);
        w.addFeedback(add(std::move(c), "point2point fixed"));
    }
    {  // point-to-point pair, breakable (strong enough to hold here)
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        btTypedConstraint* c = add(std::make_unique<btPoint2PointConstraint>(*a, *b, btVector3(btScalar(0.5), 0, 0),
                                                                             btVector3(btScalar(-0.5), 0, 0)),
                                   "point2point pair");
        c->setBreakingImpulseThreshold(50);
        w.addFeedback(c);
    }
    {  // point-to-point pair with a threshold low enough that its rows are clamped to it
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift * 4);
        btRigidBody* b = box(p + apart, -drift * 4, spin);
        add(std::make_unique<btPoint2PointConstraint>(*a, *b, btVector3(btScalar(0.5), 0, 0), btVector3(btScalar(-0.5), 0, 0)),
            "point2point breakable")
            ->setBreakingImpulseThreshold(btScalar(0.05));
    }
    {  // point-to-point to a kinematic body moving sideways
        const btVector3 p = spot();
        btRigidBody* k = w.addKinematicBox(btVector3(btScalar(0.2), btScalar(0.2), btScalar(0.2)), at(p), btVector3(1, 0, 0));
        btRigidBody* b = box(p - btVector3(0, 1, 0), drift, spin);
        add(std::make_unique<btPoint2PointConstraint>(*k, *b, btVector3(0, btScalar(-0.5), 0), btVector3(0, btScalar(0.5), 0)),
            "point2point kinematic");
    }
    {  // hinge to the fixed body, with limits and a motor
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btHingeConstraint>(*a, btVector3(btScalar(0.4), btScalar(0.2), 0), btVector3(0, 0, 1));
        c->setLimit(btScalar(-0.5), btScalar(0.5));
        c->enableAngularMotor(true, 2, 5);
        w.addFeedback(add(std::move(c), "hinge fixed limits motor"));
    }
    {  // hinge to a static body, own ERP and CFM
        const btVector3 p = spot();
        btRigidBody* beam = staticBeam(p + btVector3(0, 1, 0));
        btRigidBody* a = box(p, drift, spin);
        auto c = std::make_unique<btHingeConstraint>(*a, *beam, btVector3(0, btScalar(0.5), 0), btVector3(0, btScalar(-0.5), 0),
                                                     btVector3(1, 0, 0), btVector3(1, 0, 0));
        c->setParam(BT_CONSTRAINT_STOP_ERP, btScalar(0.6));
        c->setParam(BT_CONSTRAINT_CFM, btScalar(0.001));
        c->setLimit(btScalar(-0.2), btScalar(0.2));
        add(std::move(c), "hinge static");
    }
    {  // hinge pair with limits and more iterations than the world's
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        auto c = std::make_unique<btHingeConstraint>(*a, *b, btVector3(btScalar(0.5), 0, 0), btVector3(btScalar(-0.5), 0, 0),
                                                     btVector3(0, 0, 1), btVector3(0, 0, 1));
        c->setLimit(-1, 1, btScalar(0.9), btScalar(0.3), 1);
        c->setOverrideNumSolverIterations(20);
        add(std::move(c), "hinge pair limits");
    }
    {  // a disabled hinge: no rows, as with SI
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift);
        add(std::make_unique<btHingeConstraint>(*a, *b, btVector3(btScalar(0.5), 0, 0), btVector3(btScalar(-0.5), 0, 0),
                                                btVector3(0, 0, 1), btVector3(0, 0, 1)),
            "hinge disabled")
            ->setEnabled(false);
    }
    {  // hinge2: a wheel on a chassis, steering limited
        const btVector3 p = spot();
        btRigidBody* chassis = box(p, drift);
        btRigidBody* wheel = box(p + btVector3(1, 0, 0), -drift, spin);
        btVector3 anchor = p + btVector3(1, 0, 0), axis1(0, 1, 0), axis2(1, 0, 0);
        auto c = std::make_unique<btHinge2Constraint>(*chassis, *wheel, anchor, axis1, axis2);
        c->setLowerLimit(btScalar(-0.4));
        c->setUpperLimit(btScalar(0.4));
        w.addFeedback(add(std::move(c), "hinge2 pair"));
    }
    {  // universal pair, limited
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift, spin);
        btRigidBody* b = box(p + apart, -drift);
        btVector3 anchor = p + apart * btScalar(0.5), axis1(0, 0, 1), axis2(0, 1, 0);
        auto c = std::make_unique<btUniversalConstraint>(*a, *b, anchor, axis1, axis2);
        c->setLowerLimit(btScalar(-0.5), btScalar(-0.4));
        c->setUpperLimit(btScalar(0.5), btScalar(0.4));
        add(std::move(c), "universal pair");
    }
    {  // universal to a static body
        const btVector3 p = spot();
        btRigidBody* beam = staticBeam(p + btVector3(0, 1, 0));
        btRigidBody* a = box(p, drift, spin);
        btVector3 anchor = p + btVector3(0, btScalar(0.5), 0), axis1(0, 1, 0), axis2(1, 0, 0);
        add(std::make_unique<btUniversalConstraint>(*beam, *a, anchor, axis1, axis2), "universal static");
    }
    {  // slider on the fixed body, with limits and a linear motor
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btSliderConstraint>(*a, btTransform::getIdentity(), true);
        c->setLowerLinLimit(-1);
        c->setUpperLinLimit(1);
        c->setLowerAngLimit(btScalar(-0.3));
        c->setUpperAngLimit(btScalar(0.3));
        c->setPoweredLinMotor(true);
        c->setTargetLinMotorVelocity(1);
        c->setMaxLinMotorForce(10);
        w.addFeedback(add(std::move(c), "slider fixed limits motor"));
    }
    {  // slider pair with an angular motor; B moves only in x and y
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        b->setLinearFactor(btVector3(1, 1, 0));
        auto c = std::make_unique<btSliderConstraint>(*a, *b, frameA, frameB, true);
        c->setLowerLinLimit(btScalar(-0.5));
        c->setUpperLinLimit(btScalar(0.5));
        c->setPoweredAngMotor(true);
        c->setTargetAngMotorVelocity(2);
        c->setMaxAngMotorForce(5);
        add(std::move(c), "slider pair");
    }
    {  // cone-twist to the fixed body
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btConeTwistConstraint>(*a, btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(0.5), 0)));
        c->setLimit(btScalar(0.5), btScalar(0.4), btScalar(0.3));
        add(std::move(c), "cone-twist fixed");
    }
    {  // cone-twist pair, limited, fewer iterations than the world's; A turns about y only
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift, spin);
        btRigidBody* b = box(p + apart, -drift, spin * 2);
        a->setAngularFactor(btVector3(0, 1, 0));
        auto c = std::make_unique<btConeTwistConstraint>(*a, *b, frameA, frameB);
        c->setLimit(btScalar(0.6), btScalar(0.5), btScalar(0.2), btScalar(0.9), btScalar(0.3), 1);
        c->setOverrideNumSolverIterations(5);
        w.addFeedback(add(std::move(c), "cone-twist pair"));
    }
    {  // generic 6-DoF on the fixed body: limits and motors, linear and angular
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btGeneric6DofConstraint>(*a, btTransform::getIdentity(), true);
        c->setLinearLowerLimit(btVector3(btScalar(-0.2), btScalar(-0.1), 0));
        c->setLinearUpperLimit(btVector3(btScalar(0.2), btScalar(0.1), 0));
        c->setAngularLowerLimit(btVector3(btScalar(-0.5), btScalar(-0.3), 1));  // z free (lower > upper)
        c->setAngularUpperLimit(btVector3(btScalar(0.5), btScalar(0.3), 0));
        c->getRotationalLimitMotor(2)->m_enableMotor = true;
        c->getRotationalLimitMotor(2)->m_targetVelocity = 1;
        c->getRotationalLimitMotor(2)->m_maxMotorForce = 5;
        c->getTranslationalLimitMotor()->m_enableMotor[0] = true;
        c->getTranslationalLimitMotor()->m_targetVelocity[0] = btScalar(-0.5);
        c->getTranslationalLimitMotor()->m_maxMotorForce[0] = 4;
        add(std::move(c), "6dof fixed limits motors");
    }
    {  // generic 6-DoF pair with its own ERP and CFM on some axes
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        auto c = std::make_unique<btGeneric6DofConstraint>(*a, *b, frameA, frameB, true);
        c->setLinearLowerLimit(btVector3(0, btScalar(-0.3), 0));
        c->setLinearUpperLimit(btVector3(0, btScalar(0.3), 0));
        c->setAngularLowerLimit(btVector3(btScalar(-0.4), 0, 0));
        c->setAngularUpperLimit(btVector3(btScalar(0.4), 0, 0));
        c->setParam(BT_CONSTRAINT_STOP_ERP, btScalar(0.5), 1);
        c->setParam(BT_CONSTRAINT_CFM, btScalar(0.01), 3);
        w.addFeedback(add(std::move(c), "6dof pair"));
    }
    {  // 6-DoF spring pair: a spring along y, the rest locked
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        auto c = std::make_unique<btGeneric6DofSpringConstraint>(*a, *b, frameA, frameB, true);
        c->setLinearLowerLimit(btVector3(0, -1, 0));
        c->setLinearUpperLimit(btVector3(0, 1, 0));
        c->enableSpring(1, true);
        c->setStiffness(1, 50);
        c->setDamping(1, btScalar(0.5));
        c->setEquilibriumPoint();
        add(std::move(c), "6dof spring pair");
    }
    {  // 6-DoF spring on the fixed body, a torsion spring about x
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btGeneric6DofSpringConstraint>(*a, btTransform::getIdentity(), true);
        c->setAngularLowerLimit(btVector3(-1, 0, 0));
        c->setAngularUpperLimit(btVector3(1, 0, 0));
        c->enableSpring(3, true);
        c->setStiffness(3, 20);
        c->setDamping(3, btScalar(0.8));
        add(std::move(c), "6dof spring fixed");
    }
    {  // 6-DoF spring2 pair: spring with limits, a motor, a servo
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        auto c = std::make_unique<btGeneric6DofSpring2Constraint>(*a, *b, frameA, frameB);
        c->setLinearLowerLimit(btVector3(0, btScalar(-0.5), 0));
        c->setLinearUpperLimit(btVector3(0, btScalar(0.5), 0));
        c->enableSpring(1, true);
        c->setStiffness(1, 100);
        c->setDamping(1, 2);
        c->setEquilibriumPoint(1, 0);
        c->setAngularLowerLimit(btVector3(btScalar(-0.6), 0, 1));  // z free
        c->setAngularUpperLimit(btVector3(btScalar(0.6), 0, 0));
        c->enableMotor(3, true);
        c->setTargetVelocity(3, 1);
        c->setMaxMotorForce(3, 10);
        c->enableMotor(5, true);
        c->setServo(5, true);
        c->setServoTarget(5, btScalar(0.3));
        c->setTargetVelocity(5, 2);
        c->setMaxMotorForce(5, 10);
        w.addFeedback(add(std::move(c), "6dof spring2 pair"));
    }
    {  // 6-DoF spring2 on the fixed body, bouncy limits
        btRigidBody* a = box(spot(), drift, spin);
        auto c = std::make_unique<btGeneric6DofSpring2Constraint>(*a, btTransform::getIdentity());
        c->setLinearLowerLimit(btVector3(btScalar(-0.1), 0, 0));
        c->setLinearUpperLimit(btVector3(btScalar(0.1), 0, 0));
        c->setBounce(0, btScalar(0.5));
        c->setAngularLowerLimit(btVector3(0, btScalar(-0.2), 0));
        c->setAngularUpperLimit(btVector3(0, btScalar(0.2), 0));
        add(std::move(c), "6dof spring2 fixed");
    }
    {  // fixed pair, breakable
        const btVector3 p = spot();
        btRigidBody* a = box(p, drift);
        btRigidBody* b = box(p + apart, -drift, spin);
        add(std::make_unique<btFixedConstraint>(*a, *b, frameA, frameB), "fixed pair")->setBreakingImpulseThreshold(20);
    }
    {  // fixed to a static body
        const btVector3 p = spot();
        btRigidBody* beam = staticBeam(p + btVector3(0, 1, 0));
        btRigidBody* a = box(p, drift, spin);
        w.addFeedback(add(std::make_unique<btFixedConstraint>(*beam, *a, btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(-0.5), 0)),
                                                              btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(0.5), 0))),
                          "fixed static"));
    }
    {  // gear: two wheels on hinges to the fixed body, turning 2:1
        const btVector3 p = spot();
        btRigidBody* a = box(p, btVector3(0, 0, 0), btVector3(0, 0, 3));
        btRigidBody* b = box(p + apart * 2, btVector3(0, 0, 0), btVector3(0, 0, -1));
        add(std::make_unique<btHingeConstraint>(*a, btVector3(0, 0, 0), btVector3(0, 0, 1)), "hinge fixed (gear's)");
        add(std::make_unique<btHingeConstraint>(*b, btVector3(0, 0, 0), btVector3(0, 0, 1)), "hinge fixed (gear's)");
        w.addFeedback(add(std::make_unique<btGearConstraint>(*a, *b, btVector3(0, 0, 1), btVector3(0, 0, 1), 2), "gear pair"));
    }
    return names;
}

}  // namespace testworld
