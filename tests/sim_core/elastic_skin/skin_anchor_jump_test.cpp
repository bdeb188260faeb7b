// The dynamic skin's anchor-acceleration cap (SkinTick::
// max_anchor_acceleration): a bone that jumps within a tick carries the
// skin with it instead of hitting it with its dashpots' whole impulse, and
// a motion whose accelerations stay below the cap runs bit for bit as
// without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "dynamic_skin_fixture.hpp"

using sinew::test::DynamicSkin;
using sinew::test::to_accel;

namespace {

// One vertex on its anchor: model stiffness 1 x stiffness_scale 50 N/unit,
// 0.01 kg, anchor dashpot 0.5 N s/unit (the solver's defaults): omega =
// sqrt(5000) rad/s, c / m = 50 /s.
constexpr double kOmega = 70.71067811865476;
constexpr double kCap = 500.0;  // units / s^2

// Largest |skin - anchor| (units) over `ticks` 1 kHz ticks after the bone
// jumps `jump` units along x within tick 10.
double worst_offset_after_jump(double jump, int32_t cap, int ticks) {
  DynamicSkin s;
  s.add_vertex(0, 0, 0, 1.0);
  s.max_anchor_acceleration = cap;
  EXPECT_TRUE(s.finish());
  double worst = 0;
  for (int k = 0; k < ticks; ++k) {
    s.move_bone(k >= 10 ? jump : 0.0, 0, 0);
    EXPECT_TRUE(s.step(1000).ok());
    worst = std::max(worst, std::fabs(s.pos(0, 0) - (k >= 10 ? jump : 0.0)));
  }
  return worst;
}

}  // namespace

TEST(SkinAnchorJump, AJumpCarriesTheSkinInsteadOfFlingingIt) {
  constexpr double kJump = 0.5;  // units within one 1 ms tick: 500 units/s
  const double capped = worst_offset_after_jump(kJump, to_accel(kCap), 500);
  const double free = worst_offset_after_jump(kJump, 0, 500);
  // With the cap the skin feels two velocity kicks of at most a_max T (the
  // anchor starting, then stopping, one tick later); a damped oscillator's
  // response to a kick dv never exceeds dv / omega, so |offset| <= 2 a_max T
  // / omega, plus 16 LSB of rounding.
  const double bound = 2 * kCap * 1e-3 / kOmega + 16.0 / 1048576.0;
  std::printf("jump of %.2f units in a tick: |skin - anchor| up to %.5f with the cap (bound %.5f), %.5f without\n",
              kJump, capped, bound, free);
  EXPECT_LE(capped, bound);
  // Without it the skin lags the whole jump at first: it is the cap that
  // keeps the skin on the limb.
  EXPECT_GT(free, 0.5 * kJump);
}

TEST(SkinAnchorJump, MotionBelowTheCapRunsAsWithout) {
  // A sway of 0.01 units at 2 Hz accelerates the anchor by at most
  // 0.01 (4 pi)^2 = 1.6 units/s^2 per tick, far below 500: the cap never
  // acts, and the outputs are those of a run without it, bit for bit.
  const auto run = [](int32_t cap) {
    DynamicSkin s;
    s.add_vertex(0, 0, 0, 1.0);
    s.add_vertex(0.1, 0, 0, 0.5);
    s.add_edge(0, 1, 1.0, 0.1);
    s.max_anchor_acceleration = cap;
    EXPECT_TRUE(s.finish());
    std::vector<int32_t> out;
    for (int k = 0; k < 1000; ++k) {
      s.move_bone(0, 0.01 * std::sin(4 * M_PI * k / 1000.0), 0);
      EXPECT_TRUE(s.step(1000).ok());
      EXPECT_EQ(s.state.stats.carried, 0u);
      for (int a = 0; a < 3; ++a) out.push_back(s.state.position[a][1]);
    }
    return out;
  };
  EXPECT_EQ(run(to_accel(kCap)), run(0));
}
