// The elbow bar-net layer (docs/barnet.md) in the daemon: built once at
// start-up from the built-in arm's spec (the rig blob has no bar-net section
// yet), stepped after skinning every tick; the wrapped skin vertices replace
// the skinned ones. Normals keep the skinning's.
#pragma once

#include <memory>
#include <string>

#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

std::unique_ptr<PoseLayer> make_arm_barnet_layer(const rig::Rig& rig, std::string* error);

}  // namespace sinew::firmware
