// The frames on the arc shared by the vertices with the same balls and
// weights (sim_core/metaballs/shared_frames.cpp): the deformation stage
// writes the same words with them as with one frame per vertex, by every
// kernel, with the balls' scales at 1 and away from it; and the arm's rings
// do share them.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "arm_scene.hpp"
#include "sim_core/metaballs/kernels.hpp"

namespace sinew::test {
namespace {

namespace mbd = metaballs::detail;

// The arm's poses compared: shoulder, elbow, forearm twist (degrees).
constexpr double kSharedFramePoses[][3] = {{0, 0, 0}, {30, 90, 0}, {-20, 135, 180}, {60, 10, -90}, {0, 150, 45}};

struct SharedFramesDeformed {
  std::vector<int32_t> axis[3];
  std::vector<fx::Vec3> laplacian;
};

SharedFramesDeformed deform_with(ArmScene& scene, mbd::DeformKernel kernel, bool shared) {
  const metaballs::MetaballModel& m = scene.model();
  metaballs::MetaballState& s = scene.state();
  SharedFramesDeformed d;
  for (auto& a : d.axis) a.assign(m.vertex_count, 0x5A5A5A5A);
  skin::SkinnedVertices out;
  for (int a = 0; a < 3; ++a) out.position[a] = d.axis[a];
  s.features.shared_frames = shared;
  mbd::deform_vertices(m, scene.engine().model, &s, out, kernel);
  s.features.shared_frames = true;
  d.laplacian.assign(s.jv_posed_laplacian.begin(), s.jv_posed_laplacian.end());
  return d;
}

void expect_same_words(ArmScene& scene, const char* what) {
  for (const mbd::DeformKernel kernel : {mbd::DeformKernel::kScalar, mbd::DeformKernel::kAvx2}) {
    if (!mbd::deform_kernel_supported(kernel)) continue;
    const SharedFramesDeformed own = deform_with(scene, kernel, false), shared = deform_with(scene, kernel, true);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(own.axis[a], shared.axis[a]) << what << ", kernel " << int(kernel);
    EXPECT_EQ(own.laplacian, shared.laplacian) << what << ", kernel " << int(kernel);
  }
}

metaballs_build::Options bulging_arm() {
  metaballs_build::Options o = arm_options();
  // Over the elbow, where the balls of two bones and the joint region are.
  o.bulge.push_back({"shoulder", 0.6, 1.0, "shoulder", "elbow", 0.3});
  o.bulge.push_back({"elbow", 0.0, 0.4, "shoulder", "elbow", 0.3});
  return o;
}

TEST(MetaballSharedFrames, WriteTheWordsOfOneFramePerVertex) {
  ArmScene scene(rigc::SkinChoice::kDualQuaternion, bulging_arm());
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_FALSE(scene.model().bulges.empty());
  for (const auto& p : kSharedFramePoses) {
    ASSERT_TRUE(scene.pose(p[0], p[1], p[2]));
    expect_same_words(scene, "pose");
  }
}

// Every ball scaled differently (in [1, 2), as a bulge makes it): each
// vertex of a key blends its own scaled displacements.
TEST(MetaballSharedFrames, WriteTheWordsOfOneFramePerVertexWithEveryBallScaled) {
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(scene.pose(-20, 120, 90));
  metaballs::MetaballState& s = scene.state();
  for (uint32_t b = 0; b < scene.model().ball_count(); ++b)
    s.ball_scale[b] = fx::kUnitOne + static_cast<fx::Unit>((uint64_t{b} * 2654435761u) % (uint64_t{1} << 30));
  expect_same_words(scene, "scaled balls");
  s.ball_scale[0] = fx::kUnitOne + 1;  // one ball just off 1, the rest at 1
  for (uint32_t b = 1; b < scene.model().ball_count(); ++b) s.ball_scale[b] = fx::kUnitOne;
  expect_same_words(scene, "one ball scaled");
}

// The index: every vertex that may turn on the arc has a key, a key's
// vertices have its first vertex's balls and weights, and the arm's rings
// share keys (its weights are made per ring: docs/metaballs.md, "Shared
// frames"). One key per vertex would pass the tests above and save nothing.
TEST(MetaballSharedFrames, TheArmsRingsShareTheirKeys) {
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  const metaballs::MetaballModel& m = scene.model();
  const metaballs::MetaballState& s = scene.state();
  std::vector<bool> eq1(m.vertex_count, false);
  for (uint32_t i = 0; i < m.jv_count(); ++i) eq1[m.jv_vertex[i]] = m.jv_alpha[i] != fx::kUnitOne;
  uint32_t keyed = 0;
  for (uint32_t v = 0; v < m.vertex_count; ++v) {
    const bool candidate = eq1[v] || s.vertex_bone[v] == metaballs::kNoBall;
    ASSERT_EQ(s.vertex_frame[v] != metaballs::kNoFrame, candidate) << "vertex " << v;
    if (!candidate) continue;
    ++keyed;
    ASSERT_LT(s.vertex_frame[v], s.frame_count);
    const uint32_t first = s.frame_vertex[s.vertex_frame[v]];
    EXPECT_LE(first, v);
    for (uint32_t k = 0; k < metaballs::kVertexBalls; ++k) {
      EXPECT_EQ(m.vertex_ball[size_t{v} * 4 + k], m.vertex_ball[size_t{first} * 4 + k]) << "vertex " << v;
      EXPECT_EQ(m.vertex_weight[size_t{v} * 4 + k], m.vertex_weight[size_t{first} * 4 + k]) << "vertex " << v;
    }
  }
  EXPECT_LE(keyed, mbd::shared_frame_candidates(m));
  std::printf("shared frames: %u keys for %u vertices that may turn on the arc (of %u)\n", s.frame_count, keyed,
              m.vertex_count);
  // A ring of the arm's tube has 32 vertices; a key per ring of each
  // ball set would give 1/32. Several rings share a ball set, and the
  // weights of some ring vertices differ in their last bits.
  EXPECT_LT(s.frame_count * 4, keyed);
}

}  // namespace
}  // namespace sinew::test
