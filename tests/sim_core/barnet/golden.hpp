// Committed golden hashes of the bar-net layer. A numerics change updates
// these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::barnet::golden {
inline constexpr uint64_t kArmModel = 0xd100f8d5c00ba24au;
inline constexpr uint64_t kArmOutputs = 0x91a4a4dee97054cdu;
// The elbow net with q from an input (re-factorised every step) and with
// its loads from a force input; the paper's Figure 3 and 6 nets on the arm;
// the muscle and wrinkle nets of any rig on the built-in hand.
inline constexpr uint64_t kArmQInput = 0xa3fcc3e2debf79d3u;
inline constexpr uint64_t kArmForceInput = 0x98bebf9676661898u;
inline constexpr uint64_t kArmFigure3 = 0xdf207e640279bcf5u;
inline constexpr uint64_t kArmFigure6 = 0x176055121e223ea3u;
inline constexpr uint64_t kHandMuscles = 0x92e6a9b2655cf30du;
inline constexpr uint64_t kHandWrinkles = 0x5090feee7d44b86bu;
// The paper's nets on the shared glTF models (tests/sim_core/barnet/data/*.toml)
// through the pipeline (barnet_any_rig_test.cpp; host builds only).
inline constexpr uint64_t kRiggedFigureNets = 0xc72a6b3fe3a9f59du;
inline constexpr uint64_t kGenericHandNets = 0x2af2822a5a9b4e81u;
}  // namespace sinew::test::barnet::golden
