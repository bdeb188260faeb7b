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
#include "tests/support/test_workers.hpp"

using sinew::test::ArmAnatomy;
namespace det = sinew::determinism;

namespace anatomy_determinism_test {

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

// The built models, then every step's muscle vertices, relaxed skin and
// statistics; the skin's loops over `workers` (null: this thread).
uint64_t arm_digest(const sinew::layer::Workers* workers, uint32_t* reactions, ArmAnatomy* arm, int steps = kSteps) {
  det::OutputHash h;
  hash_records(h, arm->model().muscles);
  hash_records(h, arm->model().primitives);
  hash_records(h, arm->model().anchors);
  hash_records(h, arm->model().anchor_stiffness);
  hash_records(h, arm->model().fat);
  hash_records(h, arm->model().edges);
  hash_records(h, arm->model().bands);
  for (int s = 0; s < steps; ++s) {
    for (uint32_t i = 0; i < arm->rig().input_count; ++i) arm->inputs()[i] = trajectory(i, static_cast<uint32_t>(s));
    if (!arm->step(workers).ok()) return 0;
    const sinew::muscle::MuscleState& m = arm->muscles();
    for (int c = 0; c < 3; ++c)
      for (sinew::fx::Len v : m.vertex[c]) h.add_i32(v);
    for (sinew::fx::Unit sc : m.scale) h.add_i32(sc);
    const sinew::elastic_skin::SkinState& sk = arm->skin();
    for (int c = 0; c < 3; ++c)
      for (sinew::fx::Len v : sk.position[c]) h.add_i32(v);
    for (uint32_t i = 0; i < sk.stats.iterations; ++i) h.add_i32(sk.max_relax[i]);
    h.add_u32(sk.stats.reactions);
    h.add_u32(sk.stats.collisions);
    h.add_u32(sk.stats.inside_after);
    h.add_u32(sk.stats.saturated);
    *reactions += sk.stats.reactions;
  }
  return h.digest();
}

}  // namespace anatomy_determinism_test

TEST(AnatomyDeterminism, ArmMatchesGolden) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  uint32_t reactions = 0;
  const uint64_t digest = anatomy_determinism_test::arm_digest(nullptr, &reactions, &arm);
  det::print_determinism_line("anatomy-arm", digest);
  std::printf("anatomy-arm: %d steps, %u reactions, last step max relaxation %.4f mm -> %.4f mm\n",
              anatomy_determinism_test::kSteps, reactions, arm.metres(arm.skin().stats.max_relax_first) * 1e3,
              arm.metres(arm.skin().stats.max_relax_last) * 1e3);
  EXPECT_GT(reactions, 0u) << "the trajectory should exercise the reaction constraints";
  EXPECT_EQ(digest, sinew::test::golden::kAnatomyArm) << "anatomy outputs changed";
}

// The skin step's loops over any number of workers, each range on its own
// thread in reverse order, write the same words and the same statistics
// (collisions, reactions, saturations, largest moves: the totals the ranges
// add up) as one thread. The loops must have run over the workers (a step
// that ignored them would pass trivially). Fewer relaxations and steps than
// the golden run: each loop starts a thread per range, and under qemu that
// cost dominated; the trajectory's first 8 steps already bend the elbow
// into the reactions.
TEST(AnatomyDeterminism, EveryWorkerCountMatchesOneThread) {
  constexpr int kWorkerSteps = 8;
  constexpr uint32_t kIterations = 4;  // the built-in arm's [skin] iterations
  const auto run = [&](sinew::test::ThreadPerRangeWorkers* pool, uint32_t* reactions) {
    ArmAnatomy arm;
    if (!arm.ok()) return uint64_t{0};
    arm.skin_model().params.iterations = kIterations;
    return anatomy_determinism_test::arm_digest(pool != nullptr ? pool->workers() : nullptr, reactions, &arm,
                                                kWorkerSteps);
  };
  uint32_t serial_reactions = 0;
  const uint64_t serial = run(nullptr, &serial_reactions);
  ASSERT_NE(serial, 0u);
  EXPECT_GT(serial_reactions, 0u) << "the steps should exercise the reaction constraints";
  for (const uint32_t parts : {1u, 2u, 3u, 4u, 7u}) {
    sinew::test::ThreadPerRangeWorkers pool(parts);
    uint32_t reactions = 0;
    EXPECT_EQ(run(&pool, &reactions), serial) << parts << " workers";
    EXPECT_EQ(reactions, serial_reactions) << parts << " workers";
    if (parts > 1) {
      EXPECT_GT(pool.loops(), 0u) << parts << " workers: no loop ran over the workers";
    }
  }
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
  for (int s = 0; s < anatomy_determinism_test::kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i)
      arm.inputs()[i] = anatomy_determinism_test::trajectory(i, static_cast<uint32_t>(s));
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
  std::printf("anatomy-arm-dynamic: %d steps, %u reactions, last step largest move %.4f mm\n",
              anatomy_determinism_test::kSteps, reactions, arm.metres(arm.skin().stats.residual) * 1e3);
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
  for (int s = 0; s < anatomy_determinism_test::kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i)
      arm.inputs()[i] = anatomy_determinism_test::trajectory(i, static_cast<uint32_t>(s));
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
  std::printf("anatomy-arm-relaxation: %d steps, %u reactions, last sweep's largest move %.4f mm\n",
              anatomy_determinism_test::kSteps, reactions, arm.metres(arm.skin().stats.max_relax_last) * 1e3);
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
  anatomy_determinism_test::hash_records(h, arm.model().primitives);
  anatomy_determinism_test::hash_records(h, arm.model().exponents);
  uint32_t reactions = 0;
  for (int s = 0; s < anatomy_determinism_test::kSteps; ++s) {
    for (uint32_t i = 0; i < arm.rig().input_count; ++i)
      arm.inputs()[i] = anatomy_determinism_test::trajectory(i, static_cast<uint32_t>(s));
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
  std::printf("anatomy-arm-superquadric: %d steps, %u reactions\n", anatomy_determinism_test::kSteps, reactions);
  EXPECT_GT(reactions, 0u) << "the trajectory should exercise the reaction constraints";
  EXPECT_EQ(arm.skin().stats.inside_after, 0u);
  EXPECT_EQ(digest, sinew::test::golden::kAnatomyArmSuperquadric) << "general superquadric outputs changed";
}
