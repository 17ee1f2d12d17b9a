// Scenes with joints (btTypedConstraint), as free functions on a World (World.h), like Stacks.h.
// Bodies and joints are made in a fixed order, so two builds match body for body and joint for
// joint. Everything hangs or floats in the air unless said otherwise: no contacts.
#pragma once

#include "scenes/SceneRandom.h"
#include "scenes/World.h"

#include <string>
#include <vector>

namespace btscenes {

// A 1 kg sphere of radius 0.2 on a massless rod of `length` from the fixed point `pivot`,
// started `angle` radians from the vertical in the x-y plane.
btRigidBody* addPendulum(World& w, const btVector3& pivot, btScalar length, btScalar angle);

// A chain's links, and what its top link hangs from. The defaults are the tests' chains.
struct ChainStyle {
    btVector3 linkHalf{btScalar(0.1), btScalar(0.25), btScalar(0.1)};
    btScalar linkMass = 1;
    BodyOptions link;              // the links' surface (their velocities are the chain's)
    btRigidBody* hook = nullptr;   // null: the top link hangs from a fixed point
    btVector3 pivotInHook{0, 0, 0};  // with a hook: the chain's top, in the hook's frame
};

// `links` boxes hanging from `top` in a vertical line, each joined to the next at their touching
// faces by a point-to-point joint; the lowest starts at `kick`. Returns the links, top first.
std::vector<btRigidBody*> addChain(World& w, const btVector3& top, int links, const btVector3& kick,
                                   const ChainStyle& style = {});
// The tests' chain: links of 0.2 x 0.5 x 0.2 m, 1 kg, from a fixed point; the lowest starts
// `kick` m/s along x.
inline std::vector<btRigidBody*> addChain(World& w, const btVector3& top, int links, btScalar kick = 0) {
    return addChain(w, top, links, btVector3(kick, 0, 0));
}

// `links` boxes of 0.5 x 0.1 x 0.1 m and 1 kg in a horizontal line along x from `pin`, each hinged
// to the next about z at their touching ends and the first to the world at `pin`: a chain that
// swings down from where it is pinned, as a new user first builds one (its links may fall asleep).
std::vector<btRigidBody*> addHingeChain(World& w, const btVector3& pin, int links);

// Every joint type btDiscreteDynamicsWorld accepts (point-to-point, hinge, hinge2, universal,
// slider, cone-twist, generic 6-DoF, 6-DoF spring and spring2, fixed, gear), to the fixed body, to
// a static body and between two dynamic bodies, with limits and motors where the type has them;
// some with a breaking threshold, a feedback, an iteration override, their own ERP/CFM; one
// disabled, one to a kinematic body. Bodies start moving so that the joints have errors to
// correct. Returns each joint's name, in the world's joint order.
std::vector<std::string> addJointZoo(World& w);

// A ragdoll of 11 boxes joined by 10 limited joints (after Bullet's ragdoll demo): cone-twist
// joints at the neck, hips and shoulders, hinges at the waist, knees and elbows. 1.65 m tall,
// arms spread, about 80 kg (density 1000), with the demo's damping (0.05 linear, 0.85 angular),
// so that limbs come to rest instead of flailing. `pose` places the upright figure (pelvis at its
// origin). Returns its bodies, pelvis first.
std::vector<btRigidBody*> addRagdoll(World& w, const btTransform& pose, const BodyOptions& surface = {});

// The joint types of the random scene, in the order of their ids.
enum class JointKind {
    Point2Point, Hinge, Hinge2, Universal, Slider, ConeTwist, Generic6Dof, Spring6Dof, Spring2, Fixed, Gear, Count
};
const char* jointKindName(JointKind k);

// A seeded random scene of every joint type of the list above (JointKind), hanging in the air:
// `clusters` clusters 8 m apart (out of each other's reach), `perRow` to a row, each a chain of one to three boxes
// of random size and mass from a static hook or the fixed body, each joined to the one above by
// a joint of a random kind, with random axes, limits, motors and springs that hold the starting
// pose; the bodies start with random velocities. Every cluster whose number is 10 mod 11 is two
// wheels on hinges to the fixed body, geared; the first joint of the others takes each other kind
// in turn (11 clusters have them all). Returns each joint's kind, in the world's joint order.
std::vector<JointKind> addRandomJointScene(World& w, unsigned seed, int clusters, int perRow = 4);

// The benchmark's joint scenes, sized by one number (at least 1), each on a ground of its own
// reaching well past the scene, every body of roughSurface() (Stacks.h).

// `ragdolls` ragdolls lying face down, each turned at random about the vertical and tipped a
// little, in layers of sqrt(ragdolls / 16) a side 2 m apart (none starts touching another) and
// 0.45 m above each other: the column settles and slumps into one heap.
void groundAndRagdollPile(World& w, int ragdolls);

// Rows of eight units under static beams 12 m up, rows 4 m apart, one unit per metre of beam: a
// chain of 12 links hanging from the beam (its lowest link pushed sideways), and beside it a
// double pendulum of two rods on hinges, started level. Below every four chains a paddle of 2 t
// turns on a motor-driven hinge and strikes the chains' ends. Density 1000.
void groundAndMachine(World& w, int chains);

}  // namespace btscenes
