// Must not compile with the device side's include path: the Bullet side's headers are its own.
#include "DeviceSolver.h"
#include "BulletStep.h"
