// Compiles with the device side's include path alone: what the device side includes stands
// without Bullet (tests/CMakeLists.txt, the seam tests).
#include "DeviceFit.h"
#include "DeviceLayout.h"
#include "DeviceSolver.h"
#include "StepPlan.h"
