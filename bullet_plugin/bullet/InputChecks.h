// Checks of what a step reads from Bullet, made before anything is enqueued or written: the
// arguments of solveGroup, the solver settings, each rigid body the step solves and each
// contact point it solves. A bad value is named: a setting by its btContactSolverInfo field, a
// body by its index in the world (btCollisionObject::getWorldArrayIndex), a contact point by its
// field and the world indices of its manifold's two objects. Such input is the caller's bug, so
// the error is an InputError, which fallbackToBullet never hides.
#pragma once

#include "btOpenCLSolverError.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>

class btCollisionObject;
class btPersistentManifold;
class btRigidBody;
class btTypedConstraint;

namespace btocl {

// Bad input from the caller (a non-finite value, a negative count): always thrown.
class InputError : public btOpenCLSolverError {
public:
    using btOpenCLSolverError::btOpenCLSolverError;
};

// No count negative, no array null while its count is positive, no element of an array null.
void checkSolveGroupArguments(btCollisionObject* const* bodies, int numBodies, btPersistentManifold* const* manifolds,
                              int numManifolds, btTypedConstraint* const* constraints, int numConstraints);

// m_timeStep positive and finite, m_numIterations not negative, and every other setting the
// step reads finite (the warm-start factor with warm starting, the push settings with
// m_splitImpulse).
void checkSolverInfo(const btContactSolverInfo& info);

// A dynamic or kinematic body as the gather reads it: transform (origin and basis), velocities,
// force and torque, inverse mass, inverse inertia (local and world), linear and angular factors,
// all finite; inverse mass and local inverse inertia not negative.
void checkRigidBody(const btRigidBody& body);

// A manifold the step solves: not between an object and itself. Its points that the step solves
// (distance within the processing threshold):
// positions, normal, distance, combined friction, restitution, rolling and spinning friction;
// the warm-start impulse with warm starting; contact CFM, ERP, stiffness and damping where the
// point's flags say they are used; cached friction directions, motions and CFM where they are
// used. With `anisotropic` (a body has anisotropic friction, as the gather found), that object's
// factors and rotation.
void checkManifold(const btPersistentManifold& manifold, const btContactSolverInfo& info, bool anisotropic);

}  // namespace btocl
