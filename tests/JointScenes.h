// Scenes with joints (btTypedConstraint), as free functions on a World (TestWorld.h), from the
// scenes library that the benchmark builds too (scenes/Joints.h). Bodies and joints are made in
// a fixed order, so two builds match body for body and joint for joint. Everything hangs or
// floats in the air unless said otherwise: no contacts.
#pragma once

#include "TestWorld.h"
#include "scenes/Joints.h"

namespace testworld {

using btscenes::addChain;
using btscenes::addJointZoo;
using btscenes::addPendulum;
using btscenes::addRagdoll;
using btscenes::addRandomJointScene;
using btscenes::JointKind;
using btscenes::jointKindName;
using btscenes::SceneRandom;

}  // namespace testworld
