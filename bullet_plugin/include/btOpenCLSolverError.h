// btOpenCLSolverError, the one exception type of btOpenCLConstraintSolver (its public header
// includes this one). Apart so that the library's device side, which sees no Bullet header, can
// throw it too.
#pragma once

#include "btOpenCLSolverExport.h"

#include <stdexcept>

// Every error the solver reports: no device, a kernel build failure (with the compiler's log),
// a device error mid-step, non-finite input from the world (named: a setting by its field, a
// body by its world index), sizes past the device's limits. A step that throws has changed
// nothing in the world, and the solver steps on. btDiscreteDynamicsWorld::stepSimulation skips
// its clearForces() when the step throws: a caller who catches and steps on calls
// world.clearForces() first, or the forces (gravity too) of the failed step count twice.
class BTOCL_API btOpenCLSolverError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};
