// Committed golden hashes of the bar-net layer. A numerics change updates
// these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::barnet::golden {
inline constexpr uint64_t kArmModel = 0x94806c551feb6e37u;
inline constexpr uint64_t kArmOutputs = 0x858047153d96a248u;
// The elbow net with q from an input (re-factorised every step) and with
// its loads from a force input; the paper's Figure 3 and 6 nets on the arm;
// the muscle and wrinkle nets of any rig on the built-in hand.
inline constexpr uint64_t kArmQInput = 0x4991d8711fd8fbf8u;
inline constexpr uint64_t kArmForceInput = 0x03c4025acee3aa23u;
inline constexpr uint64_t kArmFigure3 = 0x96a8a912539aef35u;
inline constexpr uint64_t kArmFigure6 = 0x2bb96f9e05a957beu;
inline constexpr uint64_t kHandMuscles = 0xf038b50e453c2c3fu;
inline constexpr uint64_t kHandWrinkles = 0xb95c856c841e8b81u;
// The paper's nets on the shared glTF models (tests/sim_core/barnet/data/*.toml)
// through the pipeline (barnet_any_rig_test.cpp; host builds only).
inline constexpr uint64_t kRiggedFigureNets = 0x368d1f699386db4au;
inline constexpr uint64_t kGenericHandNets = 0xe06b5cdd164ea2c7u;
}  // namespace sinew::test::barnet::golden
