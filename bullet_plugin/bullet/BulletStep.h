// Where a step's records (StepProblem, plain data) came from in Bullet: the objects the
// write-back writes to and what it reads of them. Filled by StepGatherer beside the records.
#pragma once

#include "JointRows.h"

#include <LinearMath/btTransform.h>

#include <vector>

class btManifoldPoint;
class btPersistentManifold;
class btRigidBody;

namespace btocl {

struct BulletStep {
    std::vector<btRigidBody*> original;        // per solver body; null for the fixed body
    std::vector<btTransform> worldTransforms;  // per solver body, at the step's start (push)
    // Per solver body, its shape's box at the step's start (a body without a shape: its centre),
    // for the global split's reach: read for dynamic bodies alone (addSplitGeometry).
    std::vector<btVector3> boxLo, boxHi;
    std::vector<btPersistentManifold*> manifoldOfConstraint;  // per constraint; null for a joint
    std::vector<btManifoldPoint*> manifoldPoints;             // per contact point
    // Whether an object of a manifold may have anisotropic friction: the gather says when none
    // has, and the host's row setup then reads no manifold's objects.
    bool mayHaveAnisotropic = true;
    // The step's joints and their rows, set up on the host as SI sets them up (JointRows.h).
    JointRowSet joints;
};

}  // namespace btocl
