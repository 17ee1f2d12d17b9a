// Must not compile with the device side's include path: Bullet's headers are the Bullet side's.
#include "DeviceSolver.h"
#include <LinearMath/btScalar.h>
