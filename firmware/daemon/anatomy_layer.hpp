// The anatomical layers (docs/anatomy.md) in the daemon: deformed-cylinder
// muscles (biceps, triceps) and the elastic skin relaxed over them, built
// once at start-up from the built-in arm's spec (the rig blob has no anatomy
// section yet). Each tick: muscles follow the bones, then the skin relaxes
// with a few warm-started iterations (LEMAN's real-time regime) and replaces
// the skinned vertices. Normals keep the skinning's.
#pragma once

#include <memory>
#include <string>

#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

std::unique_ptr<PoseLayer> make_arm_anatomy_layer(const rig::Rig& rig, int iterations, std::string* error);

}  // namespace sinew::firmware
