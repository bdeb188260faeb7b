// The built-in rigs, embedded in the daemon as compiled blobs: the same
// offline->board contract as a rig file. The build compiles them
// (sinew-builtin-rig, from rigs/arm.toml's and rigs/hand.toml's tables) and
// the assembler includes the bytes; nothing of the rig compiler is linked.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace sinew::firmware {

// The blob of built-in rig `name` ("arm", "hand"), 8-byte aligned; empty for
// an unknown name.
std::span<const uint8_t> builtin_rig_blob(std::string_view name);

}  // namespace sinew::firmware
