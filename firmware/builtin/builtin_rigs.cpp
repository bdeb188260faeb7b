#include "builtin_rigs.hpp"

// .incbin keeps the megabytes of the blobs out of the compiler: the
// assembler copies the files (SINEW_ARM_RIG_PATH, SINEW_HAND_RIG_PATH, set by
// CMake) into .rodata, 8-byte aligned, between a start and an end symbol.
#define SINEW_EMBED(symbol, path)                                                                              \
  asm(".section .rodata\n.balign 8\n.global " #symbol "\n" #symbol ":\n.incbin \"" path "\"\n.global " #symbol \
      "_end\n" #symbol "_end:\n.byte 0\n.previous\n")

SINEW_EMBED(sinew_builtin_arm_rig, SINEW_ARM_RIG_PATH);
SINEW_EMBED(sinew_builtin_hand_rig, SINEW_HAND_RIG_PATH);

extern "C" const uint8_t sinew_builtin_arm_rig[], sinew_builtin_arm_rig_end[];
extern "C" const uint8_t sinew_builtin_hand_rig[], sinew_builtin_hand_rig_end[];

namespace sinew::firmware {

std::span<const uint8_t> builtin_rig_blob(std::string_view name) {
  if (name == "arm") return {sinew_builtin_arm_rig, sinew_builtin_arm_rig_end};
  if (name == "hand") return {sinew_builtin_hand_rig, sinew_builtin_hand_rig_end};
  return {};
}

}  // namespace sinew::firmware
