// Committed golden hashes of the bar-net layer. A numerics change updates
// these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::barnet::golden {
inline constexpr uint64_t kArmModel = 0xe8197f69ee4cf1b4u;
inline constexpr uint64_t kArmOutputs = 0xe998ba658ef76f3au;
// The elbow net with q from an input (re-factorised every step) and with
// its loads from a force input; the paper's Figure 3 and 6 nets on the arm;
// the muscle and wrinkle nets of any rig on the built-in hand.
inline constexpr uint64_t kArmQInput = 0x050f03ce577a3e3bu;
inline constexpr uint64_t kArmForceInput = 0xf6aed60d8f83321cu;
inline constexpr uint64_t kArmFigure3 = 0xc6a8047169c1669bu;
inline constexpr uint64_t kArmFigure6 = 0x52549d4766c9e750u;
inline constexpr uint64_t kHandMuscles = 0x3874672ebb14688cu;
inline constexpr uint64_t kHandWrinkles = 0x31df46c2fdd9655du;
// The paper's nets on the shared glTF models (tests/sim_core/barnet/data/*.toml)
// through the pipeline (barnet_any_rig_test.cpp; host builds only).
inline constexpr uint64_t kRiggedFigureNets = 0xdd092732f1307eeau;
inline constexpr uint64_t kGenericHandNets = 0xb6c82e46fb49ba8eu;
}  // namespace sinew::test::barnet::golden
