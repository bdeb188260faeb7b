#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host_tools/determinism/engine_workload.hpp"
#include "rig_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/test_workers.hpp"

using sinew::test::degrees;
using sinew::test::LoadedRig;
namespace rigc = sinew::rigc;

namespace {

// Smallest ratio posed/rest of the cross-section areas of the arm's rings
// whose rest x lies in [x0, x1] (rings are perpendicular to the forearm axis,
// which a pure twist leaves on +x, so the area is the y-z shoelace).
double min_ring_area_ratio(LoadedRig& rig, double x0, double x1, double* at_x) {
  const int n = rigc::kArmRingSegments;
  const uint32_t rings = rig.rig().vertex_count() / static_cast<uint32_t>(n);
  double worst = 1e9;
  for (uint32_t r = 0; r < rings; ++r) {
    const uint32_t first = r * static_cast<uint32_t>(n);
    const double x = rig.spec().vertices[first].position[0];
    if (x < x0 || x > x1) continue;
    double posed = 0, rest = 0;
    for (int k = 0; k < n; ++k) {
      const uint32_t a = first + static_cast<uint32_t>(k), b = first + static_cast<uint32_t>((k + 1) % n);
      posed += rig.position(1, a) * rig.position(2, b) - rig.position(1, b) * rig.position(2, a);
      const auto& pa = rig.spec().vertices[a].position;
      const auto& pb = rig.spec().vertices[b].position;
      rest += pa[1] * pb[2] - pb[1] * pa[2];
    }
    const double ratio = std::fabs(posed) / std::fabs(rest);
    if (ratio < worst) {
      worst = ratio;
      *at_x = x;
    }
  }
  return worst;
}

}  // namespace

TEST(Engine, RestPoseReproducesRestVertices) {
  LoadedRig arm(rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  ASSERT_TRUE(arm.step());
  double worst = 0;
  for (uint32_t v = 0; v < arm.rig().vertex_count(); ++v)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(arm.position(c, v) - arm.spec().vertices[v].position[static_cast<size_t>(c)]));
  std::printf("engine: rest pose max deviation %.3g m\n", worst);
  EXPECT_LT(worst, 1e-6);
}

TEST(Engine, DualQuaternionsKeepTheWristSectionUnderTwistWhileLinearBlendCollapses) {
  LoadedRig dqs(rigc::builtin_arm(rigc::SkinChoice::kDualQuaternion));
  LoadedRig lbs(rigc::builtin_arm(rigc::SkinChoice::kLinear));
  ASSERT_TRUE(dqs.ok() && lbs.ok());
  for (LoadedRig* r : {&dqs, &lbs}) {
    r->inputs()[static_cast<size_t>(r->input("forearm_twist.0"))] = degrees(90);
    ASSERT_TRUE(r->step());
  }
  double x_dqs = 0, x_lbs = 0;
  const double dqs_ratio = min_ring_area_ratio(dqs, 0.36, 0.50, &x_dqs);
  const double lbs_ratio = min_ring_area_ratio(lbs, 0.36, 0.50, &x_lbs);
  std::printf(
      "candy wrapper, 90 deg forearm twist: smallest cross-section area / rest: DQS %.4f (x=%.3f m), "
      "LBS %.4f (x=%.3f m)\n",
      dqs_ratio, x_dqs, lbs_ratio, x_lbs);
  EXPECT_GT(dqs_ratio, 0.95);
  EXPECT_LT(dqs_ratio, 1.05);
  EXPECT_LT(lbs_ratio, 0.80);  // the candy-wrapper collapse
}

TEST(Engine, JointLimitsClampAndFlag) {
  LoadedRig arm(rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  arm.inputs()[static_cast<size_t>(arm.input("elbow.0"))] = degrees(170);  // limit 150
  ASSERT_TRUE(arm.step());
  EXPECT_EQ(arm.engine().stats.clamped_dofs, 1u);
  const int elbow = rigc::joint_index(arm.spec(), "elbow");
  EXPECT_TRUE(arm.engine().joint_flags[static_cast<size_t>(elbow)] & sinew::skeleton::kJointClamped);
  // Clamped to 150 degrees: the same pose as commanding 150 exactly.
  std::vector<int32_t> clamped(arm.engine().vertices.position[0].begin(), arm.engine().vertices.position[0].end());
  arm.inputs()[static_cast<size_t>(arm.input("elbow.0"))] = degrees(150);
  ASSERT_TRUE(arm.step());
  EXPECT_EQ(arm.engine().stats.clamped_dofs, 0u);
  EXPECT_TRUE(std::equal(clamped.begin(), clamped.end(), arm.engine().vertices.position[0].begin()));
}

TEST(Engine, SynergyCouplesDipToPip) {
  LoadedRig hand(rigc::builtin_hand());
  ASSERT_TRUE(hand.ok());
  hand.inputs()[static_cast<size_t>(hand.input("index_pip.0"))] = degrees(60);
  ASSERT_TRUE(hand.step());
  const int dip = rigc::joint_index(hand.spec(), "index_dip");
  const sinew::fx::Quat q = hand.engine().locals[static_cast<size_t>(dip)].rotation;
  const double angle = 2 * std::atan2(std::hypot(q.x, q.y, q.z), static_cast<double>(q.w)) * 180 / M_PI;
  std::printf("synergy: PIP 60 deg drives DIP %.3f deg (gain 2/3)\n", angle);
  EXPECT_NEAR(angle, 40.0, 0.01);
}

TEST(Engine, RejectsTooFewInputsAndKeepsState) {
  LoadedRig arm(rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  ASSERT_TRUE(arm.step());
  const uint64_t steps = arm.engine().stats.steps;
  std::vector<int32_t> short_inputs(2, 0);
  EXPECT_FALSE(sinew::engine::engine_step(&arm.engine(), short_inputs));
  EXPECT_EQ(arm.engine().stats.steps, steps);
}

TEST(Engine, ZeroAllocationsAcrossTenThousandSteps) {
  for (const char* name : {"arm", "hand"}) {
    rigc::RigSpec spec;
    ASSERT_TRUE(rigc::builtin_rig(name, rigc::SkinChoice::kDualQuaternion, &spec));
    LoadedRig rig(spec);
    ASSERT_TRUE(rig.ok());
    sinew::test::AllocationCounter allocations;
    for (uint32_t s = 0; s < 10000; ++s) {
      for (uint32_t i = 0; i < rig.inputs().size(); ++i) rig.inputs()[i] = sinew::determinism::trajectory_input(i, s);
      ASSERT_TRUE(rig.step());
    }
    std::printf("engine: %s, 10000 steps, %llu heap allocations\n", name,
                static_cast<unsigned long long>(allocations.allocations()));
    EXPECT_EQ(allocations.allocations(), 0u);
  }
}

// The vertex loop over any number of workers, each range on its own thread
// in reverse order, writes the same position and normal words and counts the
// same saturations as one thread, on both skinning methods and both rigs.
// (The pipeline's golden hash cannot see this: with the metaballs layer on,
// every output vertex is the layer's.)
TEST(Engine, EveryWorkerCountWritesTheSameWords) {
  const struct {
    const char* name;
    rigc::RigSpec spec;
  } rigs[] = {{"arm DQS", rigc::builtin_arm(rigc::SkinChoice::kDualQuaternion)},
              {"arm LBS", rigc::builtin_arm(rigc::SkinChoice::kLinear)},
              {"hand DQS", rigc::builtin_hand(rigc::SkinChoice::kDualQuaternion)}};
  for (const auto& [name, spec] : rigs) {
    LoadedRig one(spec);
    ASSERT_TRUE(one.ok());
    for (const uint32_t parts : {2u, 3u, 4u, 7u}) {
      LoadedRig many(spec);
      ASSERT_TRUE(many.ok());
      sinew::test::ThreadPerRangeWorkers pool(parts);
      for (int step = 0; step < 6; ++step) {
        for (size_t i = 0; i < one.inputs().size(); ++i) {
          const int32_t value = degrees(25.0 * std::sin(0.7 * step + static_cast<double>(i)));
          one.inputs()[i] = value;
          many.inputs()[i] = value;
        }
        ASSERT_TRUE(one.step());
        ASSERT_TRUE(many.step(pool.workers()));
        const sinew::skin::SkinnedVertices& a = one.engine().vertices;
        const sinew::skin::SkinnedVertices& b = many.engine().vertices;
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::equal(a.position[c].begin(), a.position[c].end(), b.position[c].begin()))
              << name << ", " << parts << " workers, step " << step << ": positions differ";
          ASSERT_TRUE(std::equal(a.normal[c].begin(), a.normal[c].end(), b.normal[c].begin()))
              << name << ", " << parts << " workers, step " << step << ": normals differ";
        }
        EXPECT_EQ(one.engine().stats.saturated, many.engine().stats.saturated) << parts << " workers";
      }
      EXPECT_GT(pool.loops(), 0u) << parts << " workers: the vertex loop never ran over the workers";
    }
  }
}
