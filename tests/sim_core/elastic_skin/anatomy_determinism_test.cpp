// Golden determinism of the anatomy layers on the built-in arm: the built
// models (the builder runs in double on every platform) and every step's
// muscle vertices, relaxed skin and statistics hash to the committed value
// on every build.
#include <gtest/gtest.h>

#include <cstring>
#include <type_traits>
#include <vector>

#include "host_tools/determinism/output_hash.hpp"
#include "sim_core/fixed/trig.hpp"
#include "tests/sim_core/elastic_skin/golden.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;
namespace det = sinew::determinism;

namespace {

template <typename T>
void hash_records(det::OutputHash& h, const std::vector<T>& records) {
  static_assert(std::has_unique_object_representations_v<T>, "no padding: the bytes are the value");
  for (const T& r : records) {
    uint32_t words[sizeof(T) / 4];
    static_assert(sizeof(T) % 4 == 0);
    std::memcpy(words, &r, sizeof(T));
    for (uint32_t w : words) h.add_u32(w);
  }
}

// A smooth sweep: input i at step s; +-45 degrees, the elbow (input 3)
// 75 +- 75 degrees so the biceps reaches the skin.
int32_t trajectory(uint32_t input, uint32_t step) {
  const sinew::fx::Angle phase = static_cast<sinew::fx::Angle>(step * (97000000u + 13000000u * input));
  const int64_t amplitude = input == 3 ? int64_t{894784853} : int64_t{1} << 29;  // 75 or 45 degrees
  return static_cast<int32_t>(((amplitude * sinew::fx::sin_unit(phase)) >> 30) + (input == 3 ? amplitude : 0));
}

constexpr int kSteps = 24;

}  // namespace

TEST(AnatomyDeterminism, ArmMatchesGolden) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  det::OutputHash h;
  hash_records(h, arm.model().muscles);
  hash_records(h, arm.model().primitives);
  hash_records(h, arm.model().anchors);
  hash_records(h, arm.model().anchor_stiffness);
  hash_records(h, arm.model().fat);
  hash_records(h, arm.model().edges);
  hash_records(h, arm.model().bands);
  uint32_t reactions = 0;
  for (int s = 0; s < kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i) arm.inputs()[i] = trajectory(i, static_cast<uint32_t>(s));
    ASSERT_TRUE(arm.step().ok());
    const sinew::muscle::MuscleState& m = arm.muscles();
    for (int c = 0; c < 3; ++c)
      for (sinew::fx::Len v : m.vertex[c]) h.add_i32(v);
    for (sinew::fx::Unit sc : m.scale) h.add_i32(sc);
    const sinew::elastic_skin::SkinState& sk = arm.skin();
    for (int c = 0; c < 3; ++c)
      for (sinew::fx::Len v : sk.position[c]) h.add_i32(v);
    for (uint32_t i = 0; i < sk.stats.iterations; ++i) h.add_i32(sk.max_relax[i]);
    h.add_u32(sk.stats.reactions);
    h.add_u32(sk.stats.collisions);
    h.add_u32(sk.stats.inside_after);
    h.add_u32(sk.stats.saturated);
    reactions += sk.stats.reactions;
  }
  const uint64_t digest = h.digest();
  det::print_determinism_line("anatomy-arm", digest);
  std::printf("anatomy-arm: %d steps, %u reactions, last step max relaxation %.4f mm -> %.4f mm\n", kSteps, reactions,
              arm.metres(arm.skin().stats.max_relax_first) * 1e3, arm.metres(arm.skin().stats.max_relax_last) * 1e3);
  EXPECT_GT(reactions, 0u) << "the trajectory should exercise the reaction constraints";
  EXPECT_EQ(digest, sinew::test::golden::kAnatomyArm) << "anatomy outputs changed";
}

TEST(AnatomyDeterminism, ArmDynamicSkinMatchesGolden) {
  ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
    s.skin.solver.dynamic = true;
    s.skin.solver.relaxation = false;  // the explicit integrator's golden
    s.skin.solver.gravity[1] = -9.81;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  det::OutputHash h;
  uint32_t reactions = 0;
  for (int s = 0; s < kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i) arm.inputs()[i] = trajectory(i, static_cast<uint32_t>(s));
    ASSERT_TRUE(arm.step().ok());
    const sinew::elastic_skin::SkinState& sk = arm.skin();
    for (int c = 0; c < 3; ++c) {
      for (sinew::fx::Len v : sk.position[c]) h.add_i32(v);
      for (int64_t v : sk.velocity[c]) h.add_i64(v);
    }
    h.add_u32(sk.stats.substeps);
    h.add_u32(sk.stats.reactions);
    h.add_u32(sk.stats.inside_after);
    h.add_i32(sk.stats.residual);
    reactions += sk.stats.reactions;
  }
  const uint64_t digest = h.digest();
  det::print_determinism_line("anatomy-arm-dynamic", digest);
  std::printf("anatomy-arm-dynamic: %d steps, %u reactions, last step largest move %.4f mm\n", kSteps, reactions,
              arm.metres(arm.skin().stats.residual) * 1e3);
  EXPECT_GT(reactions, 0u) << "the trajectory should exercise the reaction constraints";
  EXPECT_EQ(arm.skin().stats.inside_after, 0u);
  EXPECT_EQ(digest, sinew::test::golden::kAnatomyArmDynamic) << "dynamic anatomy outputs changed";
}

// The same workload with LEMAN's surface by relaxation (the builder's
// default for a dynamic skin: bend, Platt-Barr reactions, one implicit step
// a tick) and some air pressure.
TEST(AnatomyDeterminism, ArmRelaxationSkinMatchesGolden) {
  ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
    s.skin.solver.dynamic = true;
    s.skin.solver.gravity[1] = -9.81;
    s.skin.solver.pressure = 20.0;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_EQ(arm.skin_model().surface.integrator,
            static_cast<uint8_t>(sinew::elastic_skin::SkinIntegrator::kRelaxation));
  det::OutputHash h;
  uint32_t reactions = 0;
  for (int s = 0; s < kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i) arm.inputs()[i] = trajectory(i, static_cast<uint32_t>(s));
    ASSERT_TRUE(arm.step().ok());
    const sinew::elastic_skin::SkinState& sk = arm.skin();
    for (int c = 0; c < 3; ++c) {
      for (sinew::fx::Len v : sk.position[c]) h.add_i32(v);
      for (int64_t v : sk.velocity[c]) h.add_i64(v);
    }
    h.add_u32(sk.stats.reactions);
    h.add_u32(sk.stats.inside_after);
    h.add_i32(sk.stats.max_relax_last);
    reactions += sk.stats.reactions;
  }
  const uint64_t digest = h.digest();
  det::print_determinism_line("anatomy-arm-relaxation", digest);
  std::printf("anatomy-arm-relaxation: %d steps, %u reactions, last sweep's largest move %.4f mm\n", kSteps, reactions,
              arm.metres(arm.skin().stats.max_relax_last) * 1e3);
  EXPECT_GT(reactions, 0u) << "the trajectory should exercise the reaction constraints";
  EXPECT_EQ(digest, sinew::test::golden::kAnatomyArmRelaxation) << "relaxation skin outputs changed";
}

// The arm with both bellies general superquadrics (p_xy 3, p_z 2.5: the
// log-domain kernel, sim_core/fixed/log_exp): the exponents, the muscle
// frames and the static skin hash to the committed value on every build.
TEST(AnatomyDeterminism, ArmGeneralSuperquadricMatchesGolden) {
  ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
    for (auto& p : s.primitives) {
      p.exponent = 3;
      p.exponent_z = 2.5;
    }
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  det::OutputHash h;
  hash_records(h, arm.model().primitives);
  hash_records(h, arm.model().exponents);
  uint32_t reactions = 0;
  for (int s = 0; s < kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i) arm.inputs()[i] = trajectory(i, static_cast<uint32_t>(s));
    ASSERT_TRUE(arm.step().ok());
    for (const sinew::muscle::PrimitiveFrame& f : arm.muscles().primitives) {
      const sinew::muscle::SuperquadricTerms& t = f.superquadric;
      h.add_i64(t.ratio);
      h.add_i64(t.inverse_power_z);
      for (int64_t l : t.log2_extent) h.add_i64(l);
    }
    const sinew::elastic_skin::SkinState& sk = arm.skin();
    for (int c = 0; c < 3; ++c)
      for (sinew::fx::Len v : sk.position[c]) h.add_i32(v);
    h.add_u32(sk.stats.reactions);
    h.add_u32(sk.stats.inside_after);
    reactions += sk.stats.reactions;
  }
  const uint64_t digest = h.digest();
  det::print_determinism_line("anatomy-arm-superquadric", digest);
  std::printf("anatomy-arm-superquadric: %d steps, %u reactions\n", kSteps, reactions);
  EXPECT_GT(reactions, 0u) << "the trajectory should exercise the reaction constraints";
  EXPECT_EQ(arm.skin().stats.inside_after, 0u);
  EXPECT_EQ(digest, sinew::test::golden::kAnatomyArmSuperquadric) << "general superquadric outputs changed";
}
