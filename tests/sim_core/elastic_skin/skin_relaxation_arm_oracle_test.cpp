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
      std::vector<V3> anchors(o.n), normals(o.n), targets(o.band_vertex.size());
      for (size_t i = 0; i < o.n; ++i)
        for (int c = 0; c < 3; ++c) {
          anchors[i][c] = len_units(s.anchor[c][i]);
          normals[i][c] = std::ldexp(double(s.normal[c][i]), -30);
        }
      for (size_t b = 0; b < targets.size(); ++b)
        for (int c = 0; c < 3; ++c) targets[b][c] = len_units(s.band_end[c][b]);
      std::vector<OraclePrimitive> prims;
      active = 0;
      for (const mu::PrimitiveFrame& f : arm.muscles().primitives) {
        if (f.active == 0) continue;
        ++active;
        ASSERT_FALSE(mu::is_deformed(f.deformation));
        ASSERT_TRUE(f.kind == static_cast<uint8_t>(mu::PrimitiveKind::kSuperellipsoid) ||
                    f.kind == static_cast<uint8_t>(mu::PrimitiveKind::kSphere));
        OraclePrimitive p;
        p.centre = {len_units(f.centre.x), len_units(f.centre.y), len_units(f.centre.z)};
        for (int i = 0; i < 3; ++i) p.axis[i] = unit_of(f.axis[i]), p.extent[i] = len_units(f.extent[i]);
        p.exponent = f.kind == static_cast<uint8_t>(mu::PrimitiveKind::kSphere) ? 2 : f.exponent;
        ASSERT_TRUE(p.exponent == 2 || p.exponent == 4 || p.exponent == 8);
        prims.push_back(p);
      }
      // The contact threshold: a fat point within rounding of a surface.
      // Its position is rounded by half an LSB and its fat offset by one,
      // and dF/dx at the surface is at most p / (smallest extent): points
      // with |F - 1| below p 2 LSB / extent are at the threshold.
      double smallest = HUGE_VAL;
      int largest_p = 2;
      for (const OraclePrimitive& p : prims) {
        for (double e : p.extent) smallest = std::min(smallest, e);
        largest_p = std::max(largest_p, p.exponent);
      }
      const double threshold = largest_p * 2 * std::ldexp(1.0, -20) / smallest;
      std::vector<int8_t> decided(o.n);
      for (size_t i = 0; i < o.n; ++i)
        decided[i] = s.reaction_normal[0][i] != 0 || s.reaction_normal[1][i] != 0 || s.reaction_normal[2][i] != 0;
      reacting += o.step(1.0 / hz, anchors, normals, targets, prims, &decided, threshold);
      runtime_reacting += s.stats.reactions;
      for (size_t i = 0; i < o.n; ++i) {
        V3 d{};
        for (int c = 0; c < 3; ++c) d[c] = len_units(s.position[c][i]) - o.x[i][c];
        worst = std::max(worst, sinew::test::norm3(d));
        moved = std::max(moved, sinew::test::norm3(sinew::test::sub3(o.x[i], anchors[i])));
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
