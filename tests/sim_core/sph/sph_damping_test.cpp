// The velocity damping of the particle dynamics (v' = (1 - c dt) v, docs/sph.md
// "Gains") brings every particle to rest, whatever the sign of its velocity:
// two free particles (no neighbour within h, no pull, no load) launched in
// opposite directions stop, within the substeps the geometric decay allows,
// at mirror-image positions, having coasted no further than v0 d / (1 - d).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/sph/sph_state.hpp"
#include "sim_core/sph/sph_step.hpp"

namespace {

namespace sph = sinew::sph;
namespace fx = sinew::fx;

}  // namespace

TEST(SphDamping, EveryVelocityDecaysToRestWhateverItsSign) {
  // Rig unit 1 m; particles 10 cm apart with h = 2 cm: no pair, no pressure.
  constexpr double kLenPerMetre = 1048576.0, kDt = 1.0 / 2000.0, kC = 40.0;
  std::array<std::vector<fx::Len>, 3> rest{
      std::vector<fx::Len>{static_cast<fx::Len>(-0.05 * kLenPerMetre), static_cast<fx::Len>(0.05 * kLenPerMetre)},
      std::vector<fx::Len>{0, 0}, std::vector<fx::Len>{0, 0}};
  const std::vector<uint8_t> bone{0, 1};
  sph::SphModel model;
  sph::SphParams& p = model.params;
  p.h = static_cast<fx::Len>(0.02 * kLenPerMetre);
  p.substeps = 2;
  p.max_neighbours = 8;
  p.damping = static_cast<fx::Unit>(std::llround((1 - kC * kDt) * 1073741824.0));
  p.tau_f = sph::kDensOne;
  p.yield_count = 1;
  p.grid_radius = static_cast<fx::Len>(0.2 * kLenPerMetre);
  model.joint = {0, 1, {0, 0, int32_t{1} << 30}, {0, 0, 0}};
  for (int a = 0; a < 3; ++a) {
    model.rest_local[a] = rest[static_cast<size_t>(a)];
    model.rest_model[a] = rest[static_cast<size_t>(a)];
  }
  model.bone = bone;
  const std::array<fx::Mat34, 2> transforms{fx::mat34_identity(), fx::mat34_identity()};
  std::vector<uint64_t> arena(sph::sph_state_bytes(model) / 8 + 1);
  sph::SphState st;
  ASSERT_TRUE(sph::sph_init(model, transforms, arena.data(), arena.size() * 8, &st).ok());

  // Launched at +-v0 on every axis (0.19 m/s: 100 LSB per substep).
  constexpr int32_t kV0 = 100;
  for (int a = 0; a < 3; ++a) {
    st.velocity[a][0] = -kV0;
    st.velocity[a][1] = kV0;
  }
  // |v_k| <= v0 d^k while the decay is exact; truncation toward zero only
  // takes more: at rest once v0 d^k < 1, k > ln(v0) / ln(1 / d).
  const double d = p.damping / 1073741824.0;
  const int substeps = static_cast<int>(std::ceil(std::log(kV0) / std::log(1 / d))) + 1;
  const int ticks = (substeps + 1) / 2;
  sph::SphInputs in;
  in.transforms = transforms;
  in.tresca = false;
  for (int t = 0; t < ticks; ++t) ASSERT_TRUE(sph::sph_step(&st, in).ok());
  const double coast = kV0 * d / (1 - d);
  std::printf("damping %.4f per substep: at rest after %d ticks (%d substeps); coasted %d / %d LSB (bound %.1f)\n", d,
              ticks, substeps, st.position[0][1] - rest[0][1], rest[0][0] - st.position[0][0], coast);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(st.velocity[a][0], 0) << "axis " << a << ": a negative velocity must decay to rest";
    EXPECT_EQ(st.velocity[a][1], 0) << "axis " << a << ": a positive velocity must decay to rest";
    const int64_t out = int64_t{st.position[a][1]} - rest[static_cast<size_t>(a)][1];
    const int64_t back = int64_t{rest[static_cast<size_t>(a)][0]} - st.position[a][0];
    EXPECT_EQ(out, back) << "axis " << a << ": the two must stop at mirror images";
    EXPECT_GT(out, 0);
    EXPECT_LE(static_cast<double>(out), coast);
  }
}
