// Committed golden hashes of the bar-net layer. A numerics change updates
// these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::barnet::golden {
inline constexpr uint64_t kArmModel = 0xe8197f69ee4cf1b4u;
inline constexpr uint64_t kArmOutputs = 0xc6d201c5e2e7e1f2u;
// The elbow net with q from an input (re-factorised every step) and with
// its loads from a force input; the paper's Figure 3 and 6 nets on the arm;
// the muscle and wrinkle nets of any rig on the built-in hand.
inline constexpr uint64_t kArmQInput = 0x0c703c31d3516a27u;
inline constexpr uint64_t kArmForceInput = 0xf98206e21888d152u;
inline constexpr uint64_t kArmFigure3 = 0xa1594a3f55618084u;
inline constexpr uint64_t kArmFigure6 = 0x8d45a1b781f89c8du;
inline constexpr uint64_t kHandMuscles = 0x40ba8f7b8e6d4e75u;
inline constexpr uint64_t kHandWrinkles = 0x47bd034cdc47665bu;
// The paper's nets on the shared glTF models (tests/sim_core/barnet/data/*.toml)
// through the pipeline (barnet_any_rig_test.cpp; host builds only).
inline constexpr uint64_t kRiggedFigureNets = 0xba558ff8adb39e2au;
inline constexpr uint64_t kGenericHandNets = 0x00d044cb63cff991u;
}  // namespace sinew::test::barnet::golden
