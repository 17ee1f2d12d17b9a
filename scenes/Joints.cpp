#include "scenes/Joints.h"

#include "scenes/Stacks.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace btscenes {

namespace {

// A rotation whose x axis is `x` (any y and z about it).
btMatrix3x3 basisWithX(const btVector3& x) {
    btVector3 y, z;
    btPlaneSpace1(x, y, z);
    return btMatrix3x3(x.x(), y.x(), z.x(), x.y(), y.y(), z.y(), x.z(), y.z(), z.z());
}

// The world frame `world` in the frame of body b (for a joint frame that starts where `world` is).
btTransform frameIn(const btRigidBody& b, const btTransform& world) {
    return b.getCenterOfMassTransform().inverse() * world;
}

// A 6-DoF spring of either Bullet class (they share the setters): a random stretch along x and a
// swing about x, each with a random spring; damping on x in [dampLow, dampHigh], about x in
// [swingDampLow, 1].
template <class Spring>
void randomSpringsOnX(Spring& c, SceneRandom& rng, btScalar dampLow, btScalar dampHigh, btScalar swingDampLow) {
    c.setLinearLowerLimit(btVector3(-rng.uniform(btScalar(0.2), btScalar(0.6)), 0, 0));
    c.setLinearUpperLimit(btVector3(rng.uniform(btScalar(0.2), btScalar(0.6)), 0, 0));
    c.setAngularLowerLimit(btVector3(-1, 0, 0));
    c.setAngularUpperLimit(btVector3(1, 0, 0));
    c.enableSpring(0, true);
    c.setStiffness(0, rng.uniform(20, 100));
    c.setDamping(0, rng.uniform(dampLow, dampHigh));
    c.enableSpring(3, true);
    c.setStiffness(3, rng.uniform(5, 30));
    c.setDamping(3, rng.uniform(swingDampLow, 1));
    c.setEquilibriumPoint();
}

// A joint of kind k between a (the world when a is a static body or the fixed body) and b,
// anchored at `anchor` (world), with random axes, limits, motors and springs that hold the start.
std::unique_ptr<btTypedConstraint> randomJoint(JointKind k, btRigidBody& a, btRigidBody& b, btVector3 anchor,
                                               SceneRandom& rng) {
    btVector3 axis = rng.unitVector();
    btVector3 side, third;
    btPlaneSpace1(axis, side, third);
    const btTransform world(basisWithX(axis), anchor);
    const btTransform fa = frameIn(a, world), fb = frameIn(b, world);
    const bool motor = rng.uniform() < btScalar(0.5);
    switch (k) {
        case JointKind::Point2Point:
            return std::make_unique<btPoint2PointConstraint>(a, b, fa.getOrigin(), fb.getOrigin());
        case JointKind::Hinge: {
            // Frames whose z (the hinge's axis) is `axis`: the angle starts at 0, inside the limits
            // (the constructor from pivots and axes may start it anywhere, at pi too).
            const btTransform zWorld(btMatrix3x3(side.x(), third.x(), axis.x(), side.y(), third.y(), axis.y(), side.z(),
                                                 third.z(), axis.z()),
                                     anchor);
            auto c = std::make_unique<btHingeConstraint>(a, b, frameIn(a, zWorld), frameIn(b, zWorld));
            if (rng.uniform() < btScalar(0.7))
                c->setLimit(-rng.uniform(btScalar(0.2), 1), rng.uniform(btScalar(0.2), 1));
            if (motor) c->enableAngularMotor(true, rng.uniform(-2, 2), rng.uniform(btScalar(0.05), btScalar(0.5)));
            return c;
        }
        case JointKind::Hinge2: {
            auto c = std::make_unique<btHinge2Constraint>(a, b, anchor, axis, side);
            c->setLowerLimit(-rng.uniform(btScalar(0.1), btScalar(0.6)));
            c->setUpperLimit(rng.uniform(btScalar(0.1), btScalar(0.6)));
            return c;
        }
        case JointKind::Universal: {
            auto c = std::make_unique<btUniversalConstraint>(a, b, anchor, axis, side);
            c->setLowerLimit(-rng.uniform(btScalar(0.2), 1), -rng.uniform(btScalar(0.2), 1));
            c->setUpperLimit(rng.uniform(btScalar(0.2), 1), rng.uniform(btScalar(0.2), 1));
            return c;
        }
        case JointKind::Slider: {
            auto c = std::make_unique<btSliderConstraint>(a, b, fa, fb, true);
            c->setLowerLinLimit(-rng.uniform(btScalar(0.1), btScalar(0.5)));
            c->setUpperLinLimit(rng.uniform(btScalar(0.1), btScalar(0.5)));
            c->setLowerAngLimit(-rng.uniform(0, 1));
            c->setUpperAngLimit(rng.uniform(0, 1));
            if (motor) {
                c->setPoweredLinMotor(true);
                c->setTargetLinMotorVelocity(rng.uniform(-1, 1));
                c->setMaxLinMotorForce(rng.uniform(1, 20));
            }
            return c;
        }
        case JointKind::ConeTwist: {
            auto c = std::make_unique<btConeTwistConstraint>(a, b, fa, fb);
            c->setLimit(rng.uniform(btScalar(0.2), 1), rng.uniform(btScalar(0.2), 1), rng.uniform(btScalar(0.1), 1));
            return c;
        }
        case JointKind::Generic6Dof: {
            auto c = std::make_unique<btGeneric6DofConstraint>(a, b, fa, fb, true);
            c->setLinearLowerLimit(btVector3(-rng.uniform(0, btScalar(0.3)), 0, 0));
            c->setLinearUpperLimit(btVector3(rng.uniform(0, btScalar(0.3)), 0, 0));
            c->setAngularLowerLimit(btVector3(-rng.uniform(0, 1), -rng.uniform(0, 1), -rng.uniform(0, 1)));
            c->setAngularUpperLimit(btVector3(rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 1)));
            if (motor) {
                c->getRotationalLimitMotor(0)->m_enableMotor = true;
                c->getRotationalLimitMotor(0)->m_targetVelocity = rng.uniform(-1, 1);
                c->getRotationalLimitMotor(0)->m_maxMotorForce = rng.uniform(1, 5);
            }
            return c;
        }
        case JointKind::Spring6Dof: {
            auto c = std::make_unique<btGeneric6DofSpringConstraint>(a, b, fa, fb, true);
            randomSpringsOnX(*c, rng, btScalar(0.2), 1, btScalar(0.2));
            return c;
        }
        case JointKind::Spring2: {
            auto c = std::make_unique<btGeneric6DofSpring2Constraint>(a, b, fa, fb);
            randomSpringsOnX(*c, rng, btScalar(0.5), 3, btScalar(0.1));
            if (motor) {
                c->enableMotor(4, true);  // y, locked unless the limits open it: open it for the motor
                c->setLimit(4, -1, 1);
                c->setTargetVelocity(4, rng.uniform(-1, 1));
                c->setMaxMotorForce(4, rng.uniform(1, 5));
            }
            return c;
        }
        case JointKind::Fixed:
            return std::make_unique<btFixedConstraint>(a, b, fa, fb);
        default:
            return nullptr;
    }
}

}  // namespace

btRigidBody* addPendulum(World& w, const btVector3& pivot, btScalar length, btScalar angle) {
    const btVector3 bob = pivot + btVector3(btSin(angle), -btCos(angle), 0) * length;
    btRigidBody* b = w.addSphere(btScalar(0.2), 1, at(bob));
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*b, pivot - bob));
    return b;
}

std::vector<btRigidBody*> addChain(World& w, const btVector3& top, int links, const btVector3& kick,
                                   const ChainStyle& style) {
    const btVector3& half = style.linkHalf;
    std::vector<btRigidBody*> chain;
    for (int i = 0; i < links; ++i) {
        BodyOptions o = style.link;
        o.linearVelocity = i == links - 1 ? kick : btVector3(0, 0, 0);
        // In this order the benchmark's chains keep their float positions (the tests' are exact).
        const btScalar y = top.y() - half.y() - 2 * half.y() * btScalar(i);
        chain.push_back(w.addBox(half, style.linkMass, at(btVector3(top.x(), y, top.z())), o));
    }
    const btVector3 up(0, half.y(), 0), down(0, -half.y(), 0);  // a link's top and bottom faces
    if (style.hook)
        w.addConstraint(std::make_unique<btPoint2PointConstraint>(*style.hook, *chain[0], style.pivotInHook, up));
    else
        w.addConstraint(std::make_unique<btPoint2PointConstraint>(*chain[0], up));
    for (int i = 1; i < links; ++i)
        w.addConstraint(std::make_unique<btPoint2PointConstraint>(*chain[size_t(i) - 1], *chain[size_t(i)], down, up));
    return chain;
}

std::vector<btRigidBody*> addHingeChain(World& w, const btVector3& pin, int links) {
    w.allowSleeping();
    const btVector3 half(btScalar(0.25), btScalar(0.05), btScalar(0.05));
    const btVector3 axis(0, 0, 1);
    std::vector<btRigidBody*> chain;
    for (int i = 0; i < links; ++i)
        chain.push_back(w.addBox(half, 1, at(pin + btVector3(half.x() * btScalar(2 * i + 1), 0, 0))));
    const btVector3 left(-half.x(), 0, 0), right(half.x(), 0, 0);  // a link's ends
    if (!chain.empty()) w.addConstraint(std::make_unique<btHingeConstraint>(*chain[0], left, axis));
    for (size_t i = 1; i < chain.size(); ++i)
        w.addConstraint(std::make_unique<btHingeConstraint>(*chain[i - 1], *chain[i], right, left, axis, axis));
    return chain;
}

std::vector<std::string> addJointZoo(World& w) {
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

std::vector<btRigidBody*> addRagdoll(World& w, const btTransform& pose, const BodyOptions& surface) {
    struct Part {
        btVector3 half, centre;
    };
    struct Joint {
        int a, b;
        bool hinge;
        btVector3 pivot;
        btQuaternion frame;  // turns the joint's axis (x: cone-twist's twist, z: hinge's) into place
        btScalar limit0, limit1, limit2;
    };
    const Part parts[] = {
        {{0.16f, 0.10f, 0.10f}, {0, 0.15f, 0}},        {{0.17f, 0.16f, 0.10f}, {0, 0.43f, 0}},
        {{0.09f, 0.10f, 0.09f}, {0, 0.73f, 0}},        {{0.07f, 0.22f, 0.07f}, {-0.09f, -0.17f, 0}},
        {{0.06f, 0.21f, 0.06f}, {-0.09f, -0.61f, 0}},  {{0.07f, 0.22f, 0.07f}, {0.09f, -0.17f, 0}},
        {{0.06f, 0.21f, 0.06f}, {0.09f, -0.61f, 0}},   {{0.15f, 0.05f, 0.05f}, {-0.33f, 0.53f, 0}},
        {{0.13f, 0.045f, 0.045f}, {-0.62f, 0.53f, 0}}, {{0.15f, 0.05f, 0.05f}, {0.33f, 0.53f, 0}},
        {{0.13f, 0.045f, 0.045f}, {0.62f, 0.53f, 0}},
    };
    const btScalar pi = SIMD_PI, half = SIMD_HALF_PI, quarter = SIMD_PI / 4;
    const btQuaternion aboutX(btVector3(0, 1, 0), half), aboutY(btVector3(1, 0, 0), -half);
    const btQuaternion up(btVector3(0, 0, 1), half), down(btVector3(0, 0, 1), -half);
    const btQuaternion left(btVector3(0, 0, 1), pi), right = btQuaternion::getIdentity();
    const Joint joints[] = {
        {0, 1, true, {0, 0.26f, 0}, aboutX, -quarter, half, 0},            // waist
        {1, 2, false, {0, 0.61f, 0}, up, quarter, quarter, half},          // neck
        {0, 3, false, {-0.09f, 0.05f, 0}, down, quarter, quarter, 0},      // left hip
        {3, 4, true, {-0.09f, -0.395f, 0}, aboutX, 0, half, 0},            // left knee
        {0, 5, false, {0.09f, 0.05f, 0}, down, quarter, quarter, 0},       // right hip
        {5, 6, true, {0.09f, -0.395f, 0}, aboutX, 0, half, 0},             // right knee
        {1, 7, false, {-0.175f, 0.53f, 0}, left, half, half, 0},           // left shoulder
        {7, 8, true, {-0.485f, 0.53f, 0}, aboutY, -half, 0, 0},            // left elbow
        {1, 9, false, {0.175f, 0.53f, 0}, right, half, half, 0},           // right shoulder
        {9, 10, true, {0.485f, 0.53f, 0}, aboutY, 0, half, 0},             // right elbow
    };
    std::vector<btRigidBody*> body;
    for (const Part& p : parts) {
        const btScalar mass = 1000 * 8 * p.half.x() * p.half.y() * p.half.z();
        body.push_back(w.addBox(p.half, mass, pose * at(p.centre), surface));
        body.back()->setDamping(btScalar(0.05), btScalar(0.85));
    }
    for (const Joint& j : joints) {
        const btTransform fa(j.frame, j.pivot - parts[j.a].centre), fb(j.frame, j.pivot - parts[j.b].centre);
        if (j.hinge) {
            auto hinge = std::make_unique<btHingeConstraint>(*body[size_t(j.a)], *body[size_t(j.b)], fa, fb);
            hinge->setLimit(j.limit0, j.limit1);
            w.addConstraint(std::move(hinge));
        } else {
            auto cone = std::make_unique<btConeTwistConstraint>(*body[size_t(j.a)], *body[size_t(j.b)], fa, fb);
            cone->setLimit(j.limit0, j.limit1, j.limit2);
            w.addConstraint(std::move(cone));
        }
    }
    return body;
}

const char* jointKindName(JointKind k) {
    static const char* names[] = {"point2point", "hinge", "hinge2", "universal", "slider", "cone-twist",
                                  "6dof", "6dof spring", "6dof spring2", "fixed", "gear"};
    return names[int(k)];
}

std::vector<JointKind> addRandomJointScene(World& w, unsigned seed, int clusters, int perRow) {
    SceneRandom rng(seed);
    std::vector<JointKind> kinds;
    auto add = [&](std::unique_ptr<btTypedConstraint> c, JointKind k) {
        w.addConstraint(std::move(c));
        kinds.push_back(k);
    };
    int nonGear = 0;
    for (int i = 0; i < clusters; ++i) {
        const btVector3 top(btScalar(i % perRow) * 8, 20, btScalar(i / perRow) * 8);
        auto box = [&](const btVector3& centre) {
            BodyOptions o;
            o.linearVelocity = rng.vector(1);
            o.angularVelocity = rng.vector(2);
            const btVector3 half(rng.uniform(btScalar(0.15), btScalar(0.35)), rng.uniform(btScalar(0.15), btScalar(0.3)),
                                 rng.uniform(btScalar(0.15), btScalar(0.35)));
            const btQuaternion turn(rng.unitVector(), rng.uniform(0, SIMD_PI));
            return w.addBox(half, rng.uniform(btScalar(0.5), 3), at(centre, turn), o);
        };
        if (i % 11 == 10) {  // the gear: two wheels turning about parallel axes through their centres
            const btVector3 axis = rng.unitVector();
            btRigidBody* a = box(top);
            btRigidBody* b = box(top + btVector3(2, 0, 0));
            const btVector3 axisA = a->getCenterOfMassTransform().getBasis().transpose() * axis;
            const btVector3 axisB = b->getCenterOfMassTransform().getBasis().transpose() * axis;
            add(std::make_unique<btHingeConstraint>(*a, btVector3(0, 0, 0), axisA), JointKind::Hinge);
            add(std::make_unique<btHingeConstraint>(*b, btVector3(0, 0, 0), axisB), JointKind::Hinge);
            add(std::make_unique<btGearConstraint>(*a, *b, axisA, axisB, rng.uniform(btScalar(0.5), 2)), JointKind::Gear);
            continue;
        }
        const int firstKind = nonGear++ % 10;  // each kind in turn first, then any
        const bool hook = rng.uniform() < btScalar(0.5);
        btRigidBody* above = hook ? w.addBox(btVector3(btScalar(0.1), btScalar(0.1), btScalar(0.1)), 0, at(top))
                                  : &btTypedConstraint::getFixedBody();
        btVector3 anchor = top;
        const int links = 1 + rng.below(3);
        for (int k = 0; k < links; ++k) {
            const JointKind kind = JointKind(k == 0 ? firstKind : rng.below(10));
            btRigidBody* body = box(anchor - btVector3(0, btScalar(0.5), 0));
            add(randomJoint(kind, *above, *body, anchor, rng), kind);
            above = body;
            anchor -= btVector3(0, 1, 0);
        }
    }
    return kinds;
}

void groundAndRagdollPile(World& w, int ragdolls) {
    const BodyOptions surface = roughSurface();
    // A ragdoll reaches 0.83 m from its centre and lies 0.2 m thick.
    const int n = std::max(1, ragdolls);
    const int side = std::max(1, int(std::lround(std::sqrt(double(n) / 16))));
    const btScalar spacing = 2.0f, layerHeight = 0.45f;
    w.addGround(surface, btQuaternion::getIdentity(), btScalar(side) * spacing + 20);
    SceneRandom rng = SceneRandom::fromState(4242u);
    const btScalar half = 0.5f * spacing * btScalar(side - 1);
    const btQuaternion faceDown(btVector3(1, 0, 0), SIMD_HALF_PI);
    for (int k = 0; k < n; ++k) {
        const int ix = k % side, iz = (k / side) % side, iy = k / (side * side);
        const btQuaternion yaw(btVector3(0, 1, 0), rng.uniform() * SIMD_2_PI);
        const btQuaternion tip(btVector3(rng.uniform() - 0.5f, 0, rng.uniform() - 0.5f + 1e-3f).normalized(),
                               0.05f * rng.uniform());
        const btVector3 centre(btScalar(ix) * spacing - half + 0.3f * (rng.uniform() - 0.5f),
                               0.2f + btScalar(iy) * layerHeight,
                               btScalar(iz) * spacing - half + 0.3f * (rng.uniform() - 0.5f));
        addRagdoll(w, btTransform(tip * yaw * faceDown, centre), surface);
    }
}

void groundAndMachine(World& w, int chains) {
    const BodyOptions surface = roughSurface();
    const int n = std::max(1, chains);
    const int perRow = std::min(n, 8), rows = (n + perRow - 1) / perRow;
    const btScalar density = 1000, top = 12, rowGap = 4;
    const btVector3 rodHalf(0.04f, 0.04f, 0.3f);
    const int links = 12;
    ChainStyle chain;
    chain.linkHalf = btVector3(0.05f, 0.2f, 0.05f);
    chain.linkMass = boxMass(density, chain.linkHalf);
    chain.link = surface;
    const btScalar reach = 1.6f, hub = top - 0.4f * btScalar(links) - reach + 0.5f;
    w.addGround(surface, btQuaternion::getIdentity(), btScalar(std::max(perRow, rows * 4)) + 10);
    for (int row = 0; row < rows; ++row) {
        const int units = std::min(perRow, n - row * perRow);
        const btScalar z = btScalar(row) * rowGap - 0.5f * rowGap * btScalar(rows - 1);
        const btScalar x0 = -0.5f * btScalar(perRow - 1);
        const btVector3 beamHalf(0.5f * btScalar(perRow) + 1, 0.1f, 0.1f);
        btRigidBody* beam = w.addBox(beamHalf, 0, at(btVector3(0, top + 0.1f, z)), surface);
        chain.hook = beam;
        for (int i = 0; i < units; ++i) {
            const btScalar x = x0 + btScalar(i);
            chain.pivotInHook = btVector3(x, -0.1f, 0);  // the beam's underside
            const btVector3 kick(0, 0, (row + i) % 2 ? 3.0f : -3.0f);
            addChain(w, btVector3(x, top, z), links, kick, chain);
            // The double pendulum, level along z, swinging about x.
            const btScalar xp = x + 0.5f;
            const btScalar rodMass = boxMass(density, rodHalf);
            btRigidBody* rod1 = w.addBox(rodHalf, rodMass, at(btVector3(xp, top - 0.05f, z + 0.3f)), surface);
            btRigidBody* rod2 = w.addBox(rodHalf, rodMass, at(btVector3(xp, top - 0.05f, z + 0.9f)), surface);
            w.addConstraint(std::make_unique<btHingeConstraint>(*beam, *rod1, btVector3(xp, -0.1f, 0),
                                                                btVector3(0, 0.05f, -0.3f), btVector3(1, 0, 0),
                                                                btVector3(1, 0, 0)));
            auto elbow = std::make_unique<btHingeConstraint>(*rod1, *rod2, btVector3(0, 0, 0.3f), btVector3(0, 0, -0.3f),
                                                             btVector3(1, 0, 0), btVector3(1, 0, 0));
            elbow->setLimit(-2, 2);
            w.addConstraint(std::move(elbow));
        }
        // The paddles: boards across four chains, turning about x at 1.5 rad/s, level at first
        // (clear of the chains); they strike them on their first quarter turn.
        for (int first = 0; first < units; first += 4) {
            const int last = std::min(units, first + 4) - 1;
            const btScalar x = x0 + 0.5f * btScalar(first + last);
            const btTransform level(btQuaternion(btVector3(1, 0, 0), SIMD_HALF_PI), btVector3(x, hub, z));
            const btVector3 paddleHalf(0.5f * btScalar(last - first + 1), reach, 0.08f);
            btRigidBody* paddle = w.addBox(paddleHalf, boxMass(density, paddleHalf), level, surface);
            auto axle = std::make_unique<btHingeConstraint>(*paddle, btVector3(0, 0, 0), btVector3(1, 0, 0));
            axle->enableAngularMotor(true, 1.5f, 500);
            w.addConstraint(std::move(axle));
        }
    }
}

}  // namespace btscenes
