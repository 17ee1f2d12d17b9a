// Quality measures of a simulated scene, taken the same way for both solvers' worlds.
#pragma once

#include "scenes/World.h"

#include <vector>

namespace btbench {

// Most negative contact distance over every contact point in the world (0 when none is
// negative): the deepest penetration, as a negative number.
btScalar minContactDistance(btscenes::World& w);

// Sum over dynamic bodies of 1/2 m v^2 + 1/2 w . I w.
double kineticEnergy(const btscenes::World& w);

// Centres of mass of the dynamic bodies, in body order.
std::vector<btVector3> dynamicPositions(const btscenes::World& w);

// Largest distance between the same body in two position lists of equal length.
btScalar maxDistance(const std::vector<btVector3>& a, const std::vector<btVector3>& b);

// Highest point of any dynamic box's centre (shows whether a stack still stands).
btScalar maxCentreHeight(const btscenes::World& w);

// How far a joint has come apart: the distance in world space between its pivot as body A
// carries it and as body B does, for joints that hold a point of each body together
// (point-to-point, hinge, cone-twist, fixed); -1 for other types.
btScalar jointPivotGap(const btTypedConstraint& joint);

// The largest pivot gap over the world's enabled joints; -1 when it has none that hold a point.
btScalar maxJointError(const btscenes::World& w);

}  // namespace btbench
