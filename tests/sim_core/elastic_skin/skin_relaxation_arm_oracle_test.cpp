// The whole arm's LEMAN skin with its primitives on (reaction constraints
// acting), against the double-precision oracle of the relaxation step
// (relaxation_oracle.hpp), step for step: the elbow flexes 0 -> 60 degrees
// in 0.2 s and holds, under gravity, at 100 Hz and at 1 kHz. The oracle gets
// what the upstream layers hand the skin (anchors and their normals, band
// targets, the muscles' primitive frames), computes the skin itself; each
// step starts from the runtime's state, so the comparison is step for step
// (a contact decided differently at the threshold would otherwise send the
// two on different, equally valid, paths).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/muscle/primitive_deform.hpp"
#include "tests/sim_core/elastic_skin/relaxation_oracle.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

namespace es = sinew::elastic_skin;
namespace mu = sinew::muscle;
using sinew::test::len_units;
using sinew::test::OraclePrimitive;
using sinew::test::RelaxationOracle;
using sinew::test::unit_of;
using sinew::test::V3;

TEST(SkinRelaxationArmOracle, TheArmWithItsPrimitivesStepsLikeTheOracle) {
  for (const uint32_t hz : {100u, 1000u}) {
    sinew::test::ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
      s.skin.solver.dynamic = true;
      s.skin.solver.gravity[1] = -9.81;
    });
    ASSERT_TRUE(arm.ok()) << arm.error();
    const es::SkinModel& model = arm.skin_model();
    ASSERT_EQ(model.surface.integrator, static_cast<uint8_t>(es::SkinIntegrator::kRelaxation));
    ASSERT_EQ(model.solver.edge_damping, 0) << "the oracle leaves the edge dashpots out";
    RelaxationOracle o(model);
    const int flex = int(hz / 5), ticks = int(hz / 2);
    const auto step = [&](int k) {
      arm.set("elbow.0", 60.0 * std::min(k, flex) / flex);
      EXPECT_TRUE(arm.step_muscles().ok());
      const mu::LayerStatus st = es::skin_step(model, arm.muscle_model(), arm.muscles(), arm.engine().model,
                                               es::SkinTick{hz, {}}, &arm.skin());
      EXPECT_TRUE(st.ok()) << st.message;
    };
    step(0);
    o.start(arm.skin());
    double worst = 0, moved = 0;
    size_t reacting = 0, runtime_reacting = 0;
    uint32_t active = 0;
    for (int k = 1; k <= ticks; ++k) {
      o.start(arm.skin());  // step for step: from the runtime's state
      step(k);
      const es::SkinState& s = arm.skin();
      const sinew::test::OracleInputs in = sinew::test::oracle_inputs(s, arm.muscles(), o.band_vertex.size());
      ASSERT_TRUE(in.supported) << "a primitive the oracle does not model";
      active = static_cast<uint32_t>(in.prims.size());
      reacting += o.step(1.0 / hz, in.anchors, in.normals, in.targets, in.prims, &in.decided, in.threshold);
      runtime_reacting += s.stats.reactions;
      for (size_t i = 0; i < o.n; ++i) {
        V3 d{};
        for (int c = 0; c < 3; ++c) d[c] = len_units(s.position[c][i]) - o.x[i][c];
        worst = std::max(worst, sinew::test::norm3(d));
        moved = std::max(moved, sinew::test::norm3(sinew::test::sub3(o.x[i], in.anchors[i])));
      }
    }
    // The bound, per step (each step starts from the runtime's state): a
    // sweep moves each vertex by r / D, r read from positions rounded to
    // half an LSB. The springs' weights sum below D (half an LSB); the bend
    // term reads the umbrella vectors of the vertex and its neighbours, each
    // off by up to an LSB, with weights up to twice its share of D (an LSB);
    // so 2 LSB a sweep, plus one for the push-out's last step ("+1 LSB:
    // leave the surface") and one for the start.
    const double lsb = std::ldexp(1.0, -20);
    const double bound = (2.0 * o.sweeps + 2) * lsb;
    std::printf(
        "arm at %u Hz, %d steps, %u active primitives: %zu reactions (runtime %zu; %zu at the contact threshold "
        "taken from it), skin up to %.1f mm off its anchors, largest one-step gap %.1f LSB (bound %.0f LSB)\n",
        hz, ticks, active, reacting, runtime_reacting, o.adopted, arm.metres(std::llround(moved / lsb)) * 1e3,
        worst / lsb, bound / lsb);
    // Points in resting contact sit at the surface (the law returns them
    // there), so some are at the threshold every step; the rest, the bulk,
    // are the oracle's own decisions.
    EXPECT_LT(o.adopted * 20, reacting) << "threshold cases must stay few";
    EXPECT_GT(active, 0u);
    EXPECT_GT(reacting, 0u) << "the primitives must act on the skin";
    EXPECT_LE(worst, bound) << hz << " Hz";
  }
}
