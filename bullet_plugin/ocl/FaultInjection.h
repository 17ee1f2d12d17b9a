// For tests: makes checkCl (OclRuntime.h) report a failure the device did not have, so that a
// test on a device that never fails reaches every error path of a step. Off unless a test turns
// it on; then every check counts (one relaxed atomic load per check when off).
#pragma once

#include "OclInclude.h"

namespace btocl {

// Counting from this call, the nth OpenCL result checked (1 = the next) reads as
// CL_OUT_OF_RESOURCES, and with `every`, each nth one after it too. 0 turns it off.
void injectDeviceFault(long nth, bool every = false);

// OpenCL results checked since the last injectDeviceFault call (a large nth just counts them).
long deviceResultsChecked();

// What checkCl reports for `err`: err itself, or the injected failure.
cl_int injectedResult(cl_int err);

}  // namespace btocl
