// The vector kernel of eq. (4) (normal-ball deformation) against the scalar
// specification, word for word: on the built-in arm's real states, and on
// adversarial balls and vertices (weights at 2^30 on one ball or split with
// zeros, displacements at their limits, balls that all share one rotation
// or each their own, runs of vertices with the same balls and weights, rotation "matrices" with every entry at +-1 so R
// d leaves the int32 range, bulge scales at 1 and near 2, centres at the Len limits so the result saturates).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "arm_scene.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "sim_core/fixed/norm.hpp"
#include "sim_core/metaballs/kernels.hpp"
#include "sim_core/metaballs/rotation.hpp"

namespace sinew::test {
namespace {

namespace mbd = metaballs::detail;

struct DeformOutput {
  std::vector<int32_t> axis[3];
  explicit DeformOutput(uint32_t n) {
    for (auto& a : axis) a.assign(n, 0x5A5A5A5A);  // a word neither kernel writes by chance
  }
  skin::SkinnedVertices view() {
    skin::SkinnedVertices v;
    for (int a = 0; a < 3; ++a) v.position[a] = axis[a];
    return v;
  }
};

// Runs eq. (4) by both kernels and counts the words that differ (the
// skipped vertices must be left unwritten by both).
uint32_t deform_kernels_differ(const metaballs::MetaballModel& m, const metaballs::MetaballState& s,
                               std::span<const uint32_t> skip = {}) {
  DeformOutput scalar(m.vertex_count), vector(m.vertex_count);
  mbd::deform_normal_balls_scalar(m, s, scalar.view(), skip);
  uint32_t differ = 0;
  for (const uint32_t v : skip) EXPECT_EQ(scalar.axis[0][v], 0x5A5A5A5A) << "skipped vertex " << v << " written";
#if defined(__x86_64__)
  EXPECT_TRUE(mbd::deform_normal_balls_avx2(m, s, vector.view(), skip));
  for (int a = 0; a < 3; ++a)
    for (uint32_t v = 0; v < m.vertex_count; ++v) differ += scalar.axis[a][v] != vector.axis[a][v] ? 1u : 0u;
#endif
  return differ;
}

bool avx2_deform_available() { return mbd::deform_kernel_supported(mbd::DeformKernel::kAvx2); }

uint64_t next_random(uint64_t* state) {
  *state = *state * 6364136223846793005u + 1442695040888963407u;
  return *state >> 11;
}

int32_t random_between(uint64_t* state, int64_t lo, int64_t hi) {
  return static_cast<int32_t>(lo + static_cast<int64_t>(next_random(state) % static_cast<uint64_t>(hi - lo + 1)));
}

// A random rotation: four random components divided by their norm.
fx::Quat random_unit_quat(uint64_t* rng) {
  const int32_t c[4] = {
      random_between(rng, -fx::kUnitOne, fx::kUnitOne), random_between(rng, -fx::kUnitOne, fx::kUnitOne),
      random_between(rng, -fx::kUnitOne, fx::kUnitOne), random_between(rng, -fx::kUnitOne, fx::kUnitOne)};
  const fx::NormDivisor nd = fx::norm_divisor(c, 4);
  return {fx::divide_by_norm(c[0], nd), fx::divide_by_norm(c[1], nd), fx::divide_by_norm(c[2], nd),
          fx::divide_by_norm(c[3], nd)};
}

// The arm's poses the kernels are compared on: shoulder, elbow, forearm twist (degrees).
constexpr double kPoses[][3] = {{0, 0, 0}, {30, 90, 0}, {-20, 135, 180}, {60, 10, -90}, {0, 150, 45}};

TEST(MetaballDeformKernel, MatchesTheSpecificationOnTheArm) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  for (const auto& p : kPoses) {
    ASSERT_TRUE(scene.pose(p[0], p[1], p[2]));
    EXPECT_EQ(deform_kernels_differ(scene.model(), scene.state()), 0u) << p[0] << " " << p[1] << " " << p[2];
    EXPECT_EQ(deform_kernels_differ(scene.model(), scene.state(), scene.model().jv_vertex), 0u)
        << p[0] << " " << p[1] << " " << p[2] << ", joint-region vertices skipped";
  }
}

TEST(MetaballDeformKernel, MatchesTheSpecificationOnAdversarialBalls) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(scene.pose(10, 45, 30));
  const metaballs::MetaballModel& base = scene.model();
  const uint32_t balls = base.ball_count(), n = base.vertex_count;
  const size_t slots = size_t{n} * metaballs::kVertexBalls;
  uint64_t rng = 0x5EEDF00Du;
  for (int round = 0; round < 40; ++round) {
    std::vector<uint16_t> ball(slots);
    std::vector<fx::Unit> weight(slots, 0);
    std::vector<fx::Vec3> disp(slots);
    for (uint32_t v = 0; v < n; ++v) {
      // Weights summing to 2^30: all on one ball, or a random split with zeros.
      int64_t left = fx::kUnitOne;
      for (uint32_t k = 0; k < metaballs::kVertexBalls; ++k) {
        const size_t i = size_t{v} * metaballs::kVertexBalls + k;
        ball[i] = static_cast<uint16_t>(next_random(&rng) % balls);
        const bool last = k + 1 == metaballs::kVertexBalls;
        const int64_t w =
            last || round % 4 == 0 ? left : (next_random(&rng) % 3 == 0 ? 0 : random_between(&rng, 0, left));
        weight[i] = static_cast<fx::Unit>(w);
        left -= w;
        const int32_t limit = (int32_t{1} << 30) - 1;
        disp[i] = round % 3 == 0 ? fx::Vec3{limit, -limit, limit}
                                 : fx::Vec3{random_between(&rng, -limit, limit), random_between(&rng, -limit, limit),
                                            random_between(&rng, -limit, limit)};
      }
      // Every fourth round, odd vertices take the previous vertex's balls and
      // weights (a ring's vertices), with displacements of their own.
      if (round % 4 == 3 && v % 2 == 1)
        for (uint32_t k = 0; k < metaballs::kVertexBalls; ++k) {
          const size_t i = size_t{v} * metaballs::kVertexBalls + k;
          ball[i] = ball[i - metaballs::kVertexBalls];
          weight[i] = weight[i - metaballs::kVertexBalls];
        }
    }
    std::vector<fx::Rot3> rotation(balls);
    std::vector<fx::Quat> quat(balls);
    std::vector<fx::Unit> scale(balls);
    std::vector<fx::Vec3> center(balls);
    for (uint32_t b = 0; b < balls; ++b) {
      const fx::Quat unit = random_unit_quat(&rng);
      // Every third round all balls share one rotation, so every vertex takes
      // the vector path with all its balls weighted.
      quat[b] = round % 3 == 2 && b > 0 ? quat[0] : unit;
      if (round % 5 == 1) {  // every entry at +-1: |R d| up to 3 * 2^30, beyond int32
        for (auto& row : rotation[b].m)
          for (auto& e : row) e = next_random(&rng) % 2 ? fx::kUnitOne : -fx::kUnitOne;
      } else {
        rotation[b] = round % 3 == 2 && b > 0 ? rotation[0] : fx::rot3_of_unit(unit);
      }
      const uint32_t pick = static_cast<uint32_t>(next_random(&rng) % 3);
      scale[b] = pick == 0 ? fx::kUnitOne : pick == 1 ? INT32_MAX : random_between(&rng, fx::kUnitOne, INT32_MAX);
      const int32_t reach = round % 2 ? INT32_MAX : (int32_t{1} << 24);
      center[b] = {random_between(&rng, -int64_t{reach} - (round % 2), reach), random_between(&rng, -reach, reach),
                   random_between(&rng, -reach, reach)};
    }
    metaballs::MetaballModel m = base;
    m.vertex_ball = ball;
    m.vertex_weight = weight;
    m.vertex_disp = disp;
    metaballs::MetaballState s = scene.state();
    s.ball_rotation = rotation;
    s.ball_quat = quat;
    s.ball_scale = scale;
    s.ball_center = center;
    mbd::make_rest_blends(m, &s);  // the model changed under the state
    EXPECT_EQ(deform_kernels_differ(m, s), 0u) << "round " << round;
  }
}

// The frames of eq. (4) on the arc (joint_region_frame) by the kernel chosen,
// against the specification: the number of vertices whose frame differs in
// any word.
uint32_t frame_kernels_differ(const metaballs::MetaballModel& m, const metaballs::MetaballState& s,
                              const std::vector<uint32_t>& vertices) {
  std::vector<mbd::NormalBallFrame> vector(vertices.size()), scalar(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) scalar[i] = mbd::joint_region_frame(m, s, vertices[i]);
  mbd::joint_region_frames(m, s, vertices, vector, mbd::DeformKernel::kAvx2);
  uint32_t differ = 0;
  for (size_t i = 0; i < vertices.size(); ++i) {
    const mbd::NormalBallFrame &a = scalar[i], &b = vector[i];
    bool same = a.disp == b.disp && a.quat == b.quat;
    for (int r = 0; r < 3; ++r) {
      same = same && a.centre[r] == b.centre[r];
      for (int c = 0; c < 3; ++c) same = same && a.rotation.m[r][c] == b.rotation.m[r][c];
    }
    differ += same ? 0u : 1u;
  }
  return differ;
}

// Every vertex in an order that is not ascending (the kernel takes any list),
// with a count that leaves a last group of fewer than four.
std::vector<uint32_t> shuffled_vertices(uint32_t n, uint64_t* rng) {
  std::vector<uint32_t> v(n);
  for (uint32_t i = 0; i < n; ++i) v[i] = i;
  for (uint32_t i = n; i > 1; --i) std::swap(v[i - 1], v[static_cast<size_t>(next_random(rng) % i)]);
  if (v.size() % 4 == 0 && !v.empty()) v.pop_back();
  return v;
}

TEST(MetaballJointFrameKernel, MatchesTheSpecificationOnTheArm) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  uint64_t rng = 0xF4A3E5u;
  for (const auto& p : kPoses) {
    ASSERT_TRUE(scene.pose(p[0], p[1], p[2]));
    ASSERT_TRUE(scene.state().ball_frames_near_unit);
    EXPECT_EQ(frame_kernels_differ(scene.model(), scene.state(), shuffled_vertices(scene.model().vertex_count, &rng)),
              0u)
        << p[0] << " " << p[1] << " " << p[2];
  }
}

// Random weights (with zeros, and with slots whose ball index is out of
// range where the weight is 0), random rotations on both hemispheres of each
// other, bulge scales from 1 to just below 2 with displacements at their
// limits (s d leaves int32: the lane is redone), centres and ball rests at
// the Len limits (the centre saturates), real parts of zero (the squared norm
// takes the division path) and frames beyond near unit (the whole batch is
// the specification's).
TEST(MetaballJointFrameKernel, MatchesTheSpecificationOnAdversarialFrames) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(scene.pose(10, 45, 30));
  const metaballs::MetaballModel& base = scene.model();
  const uint32_t balls = base.ball_count(), n = base.vertex_count;
  const size_t slots = size_t{n} * metaballs::kVertexBalls;
  uint64_t rng = 0x0DDBA11u;
  uint32_t redone_rounds = 0;
  for (int round = 0; round < 40; ++round) {
    std::vector<uint16_t> ball(slots);
    std::vector<fx::Unit> weight(slots, 0);
    std::vector<fx::Vec3> disp(slots);
    for (uint32_t v = 0; v < n; ++v) {
      int64_t left = fx::kUnitOne;
      for (uint32_t k = 0; k < metaballs::kVertexBalls; ++k) {
        const size_t i = size_t{v} * metaballs::kVertexBalls + k;
        const bool last = k + 1 == metaballs::kVertexBalls;
        const int64_t w = last ? left : (next_random(&rng) % 3 == 0 ? 0 : random_between(&rng, 0, left));
        weight[i] = static_cast<fx::Unit>(w);
        left -= w;
        ball[i] =
            w == 0 && next_random(&rng) % 2 ? metaballs::kNoBall : static_cast<uint16_t>(next_random(&rng) % balls);
        const int32_t limit = (int32_t{1} << 30) - 1;
        disp[i] = round % 3 == 0 ? fx::Vec3{limit, -limit, limit}
                                 : fx::Vec3{random_between(&rng, -limit, limit), random_between(&rng, -limit, limit),
                                            random_between(&rng, -limit, limit)};
        // Beyond the validated range, so s d leaves int32 where s is near 2.
        if (round % 5 == 2 && k == 0) disp[i] = {INT32_MAX, -INT32_MAX, INT32_MAX};
      }
      // With ball 0 beyond near unit: ball 0 in the first two slots with small
      // weights, so its plain dot with itself (above 2^63) would flip the
      // second slot's sign while the blend stays normalisable.
      if (round % 11 == 5 && v % 3 == 0) {
        const size_t i = size_t{v} * metaballs::kVertexBalls;
        ball[i] = ball[i + 1] = 0;
        weight[i] = weight[i + 1] = int32_t{1} << 20;
        ball[i + 2] = static_cast<uint16_t>(1 + next_random(&rng) % (balls - 1));
        weight[i + 2] = fx::kUnitOne - (int32_t{1} << 21);
        weight[i + 3] = 0;
      }
    }
    std::vector<fx::Vec3> rest(balls);
    metaballs::MetaballState s = scene.state();
    std::vector<fx::DualQuat> frame(balls);
    std::vector<fx::Unit> scale(balls);
    for (uint32_t b = 0; b < balls; ++b) {
      fx::Quat unit = random_unit_quat(&rng);
      if (round % 7 == 3 && b % 5 == 0) unit = {0, 0, 0, 0};
      if (round % 11 == 5 && b == 0) unit = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};  // beyond near unit
      const int32_t reach = round % 2 ? INT32_MAX : (int32_t{1} << 24);
      const fx::Vec3 t{random_between(&rng, -int64_t{reach} - 1, reach), random_between(&rng, -reach, reach),
                       random_between(&rng, -reach, reach)};
      frame[b] = fx::dual_quat_from_rt(unit, t);
      const int32_t rest_reach = round % 4 == 1 ? (int32_t{1} << 30) : (int32_t{1} << 22);
      rest[b] = {random_between(&rng, -rest_reach, rest_reach), random_between(&rng, -rest_reach, rest_reach),
                 random_between(&rng, -rest_reach, rest_reach)};
      const uint32_t pick = static_cast<uint32_t>(next_random(&rng) % 3);
      scale[b] = pick == 0 ? fx::kUnitOne : pick == 1 ? INT32_MAX : random_between(&rng, fx::kUnitOne, INT32_MAX);
    }
    bool near_unit = true;
    for (const fx::DualQuat& f : frame)
      for (const int64_t q : {f.real.w, f.real.x, f.real.y, f.real.z})
        near_unit = near_unit && q >= -mbd::kFrameRealLimit && q <= mbd::kFrameRealLimit;
    redone_rounds += near_unit ? 0u : 1u;
    metaballs::MetaballModel m = base;
    m.vertex_ball = ball;
    m.vertex_weight = weight;
    m.vertex_disp = disp;
    m.ball_rest = rest;
    s.ball_frame = frame;
    s.ball_scale = scale;
    s.ball_frames_near_unit = near_unit;
    mbd::make_rest_blends(m, &s);  // the model changed under the state
    EXPECT_EQ(frame_kernels_differ(m, s, shuffled_vertices(n, &rng)), 0u) << "round " << round;
  }
  EXPECT_GT(redone_rounds, 0u);  // the beyond-near-unit frames were tried
}

// Eq. (1) of every joint-region entry by the AVX2 kernel and by the
// specification, from the same frames and R_eta; returns the number of
// output words (positions and posed Laplacians) that differ.
uint32_t blend_kernels_differ(const metaballs::MetaballModel& m, std::span<const fx::Mat34> joint_model,
                              const metaballs::MetaballState& base, const std::vector<mbd::NormalBallFrame>& frame,
                              const std::vector<fx::Quat>& eta) {
  const uint32_t count = m.jv_count();
  std::vector<const mbd::NormalBallFrame*> frame_of(count);
  for (uint32_t i = 0; i < count; ++i) frame_of[i] = &frame[i];
  std::vector<fx::Vec3> laplacian_scalar(count), laplacian_vector(count);
  DeformOutput scalar(m.vertex_count), vector(m.vertex_count);
  metaballs::MetaballState s = base;
  s.jv_posed_laplacian = laplacian_scalar;
  for (uint32_t i = 0; i < count; ++i)
    mbd::blend_joint_region_entry(m, joint_model, frame[i], eta[i], i, &s, scalar.view());
  s.jv_posed_laplacian = laplacian_vector;
  // In batches of 7 from entry 3 (after the first three by the kernel too):
  // groups of four that do not start on a multiple of four, and short last groups.
  for (uint32_t first = 0; first < count;) {
    const uint32_t n = first == 0 ? std::min(3u, count) : std::min(7u, count - first);
    mbd::blend_joint_region_entries(m, joint_model, std::span(frame_of).subspan(first, n),
                                    std::span(eta).subspan(first, n), first, &s, vector.view(),
                                    mbd::DeformKernel::kAvx2);
    first += n;
  }
  uint32_t differ = 0;
  for (int a = 0; a < 3; ++a)
    for (uint32_t v = 0; v < m.vertex_count; ++v) differ += scalar.axis[a][v] != vector.axis[a][v] ? 1u : 0u;
  for (uint32_t i = 0; i < count; ++i) differ += laplacian_scalar[i] == laplacian_vector[i] ? 0u : 1u;
  return differ;
}

// R_eta of every entry, as the step makes it.
std::vector<fx::Quat> entry_eta(const metaballs::MetaballModel& m, const metaballs::MetaballState& s) {
  std::vector<fx::Quat> eta(m.jv_count());
  for (uint32_t i = 0; i < m.jv_count(); ++i) {
    const metaballs::JointBall& jb = m.joint_balls[m.jv_ball[i]];
    eta[i] = mbd::nlerp_fast(s.bone_rotation[jb.bone_a], s.bone_rotation[jb.bone_b], m.jv_blend[i]);
  }
  return eta;
}

TEST(MetaballJointBlendKernel, MatchesTheSpecificationOnTheArm) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  const metaballs::MetaballModel& m = scene.model();
  ASSERT_GT(m.jv_count(), 8u);
  for (const auto& p : kPoses) {
    ASSERT_TRUE(scene.pose(p[0], p[1], p[2]));
    std::vector<mbd::NormalBallFrame> frame(m.jv_count());
    for (uint32_t i = 0; i < m.jv_count(); ++i)
      if (m.jv_alpha[i] != fx::kUnitOne) frame[i] = mbd::joint_region_frame(m, scene.state(), m.jv_vertex[i]);
    EXPECT_EQ(blend_kernels_differ(m, scene.engine().model, scene.state(), frame, entry_eta(m, scene.state())), 0u)
        << p[0] << " " << p[1] << " " << p[2];
  }
}

// Weights at 0, 1, between, and slightly outside [0, 1] (where the blend's
// unnormalised sum leaves int32); rotations equal, antipodal, random, zero,
// beyond near unit, and a blend whose sum rounds to zero; centres far from
// the joint and displacements far apart (differences beyond int32);
// Laplacians and displacements at the Len limits (saturation). Every input
// stays where the specification is defined (no int64 overflow).
TEST(MetaballJointBlendKernel, MatchesTheSpecificationOnAdversarialEntries) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(scene.pose(10, 45, 30));
  const metaballs::MetaballModel& base = scene.model();
  const uint32_t count = base.jv_count();
  uint64_t rng = 0xB1E4Du;
  const auto random_unit = [&] { return random_unit_quat(&rng); };
  const auto random_vec = [&](int32_t reach) {
    return fx::Vec3{random_between(&rng, -reach, reach), random_between(&rng, -reach, reach),
                    random_between(&rng, -reach, reach)};
  };
  // 1.4 in Q2.30: beyond near unit, and rot3_of_unit's products still fit.
  constexpr int32_t kBig = 1503238553;
  uint32_t outside_weights = 0;
  for (int round = 0; round < 30; ++round) {
    const bool wide = round % 3 == 0;  // Len-limit vectors; weights within [0, 1]
    std::vector<fx::Unit> alpha(count);
    std::vector<fx::Vec3> disp(count), laplacian(count);
    std::vector<mbd::NormalBallFrame> frame(count);
    std::vector<fx::Quat> eta(count);
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t pick = static_cast<uint32_t>(next_random(&rng) % 8);
      const int32_t quarter = int32_t{1} << 28;
      alpha[i] = pick == 0   ? 0
                 : pick == 1 ? fx::kUnitOne
                 : pick == 2 && !wide
                     ? (next_random(&rng) % 2 ? random_between(&rng, -quarter, -1)
                                              : random_between(&rng, fx::kUnitOne + 1, fx::kUnitOne + quarter))
                     : random_between(&rng, 1, fx::kUnitOne - 1);
      outside_weights += alpha[i] < 0 || alpha[i] > fx::kUnitOne ? 1u : 0u;
      const int32_t reach = wide ? INT32_MAX : (int32_t{1} << 26);
      disp[i] = random_vec(reach);
      laplacian[i] = random_vec(reach);
      mbd::NormalBallFrame& f = frame[i];
      f.quat = random_unit();
      const uint32_t relation = static_cast<uint32_t>(next_random(&rng) % 12);
      eta[i] = relation == 0   ? f.quat
               : relation == 1 ? fx::Quat{-f.quat.w, -f.quat.x, -f.quat.y, -f.quat.z}
               : relation == 2 ? fx::Quat{0, 0, 0, 0}
               : relation == 3 ? fx::Quat{kBig, -kBig, kBig, -kBig}
                               : random_unit();
      if (relation == 4) f.quat = {0, 0, 0, 0};
      if (relation == 5) f.quat = {kBig, kBig, -kBig, kBig};
      // Where w_alpha may leave [0, 1] (the blends' sums stay below 2^63):
      constexpr int32_t kLimit = 5 << 28;  // near unit's limit, 1.25
      if (relation == 6 && !wide) {        // a sum of exactly zero: the first rotation kept
        f.quat = {0, kLimit, 0, 0};
        eta[i] = {0, 1 << 28, 0, 0};
        alpha[i] = 5 << 28;
      }
      if (relation == 7 && !wide) {  // near unit, but the sum's w leaves int32 (2.75)
        f.quat = {-kLimit, kLimit, kLimit, kLimit};
        eta[i] = {kLimit, kLimit, kLimit, kLimit};
        alpha[i] = static_cast<int32_t>(int64_t{fx::kUnitOne} * 8 / 5);
      }
      if (relation == 8) {                     // beyond near unit, both: their plain dot overflows int64 (a blend only)
        constexpr int32_t kHuge = 1556925644;  // 1.45
        f.quat = {kHuge, kHuge, -kHuge, kHuge};
        eta[i] = {kHuge, kHuge, -kHuge, kHuge - 1};
        alpha[i] = random_between(&rng, 1, fx::kUnitOne - 1);
      }
      const fx::Vec3 c = random_vec(wide ? INT32_MAX : (int32_t{1} << 26));
      f.centre[0] = c.x, f.centre[1] = c.y, f.centre[2] = c.z;
      f.disp = random_vec(reach);
      f.rotation = {};  // not read by eq. (1)
    }
    metaballs::MetaballModel m = base;
    m.jv_alpha = alpha;
    m.jv_disp = disp;
    m.jv_laplacian = laplacian;
    EXPECT_EQ(blend_kernels_differ(m, scene.engine().model, scene.state(), frame, eta), 0u) << "round " << round;
  }
  EXPECT_GT(outside_weights, 0u);
}

// The whole deformation stage (eq. (4), the frames on the arc, eq. (1)) by
// each kernel: every position and posed Laplacian word the same. The golden
// hashes see only the kernel the CPU selects; this compares the scalar
// specification's path with it on the same machine.
TEST(MetaballDeformVertices, EveryKernelWritesTheSameWords) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  const metaballs::MetaballModel& m = scene.model();
  for (const auto& p : kPoses) {
    ASSERT_TRUE(scene.pose(p[0], p[1], p[2]));
    DeformOutput scalar(m.vertex_count), vector(m.vertex_count);
    metaballs::MetaballState& s = scene.state();
    mbd::deform_vertices(m, scene.engine().model, &s, scalar.view(), mbd::DeformKernel::kScalar);
    const std::vector<fx::Vec3> laplacian_scalar(s.jv_posed_laplacian.begin(), s.jv_posed_laplacian.end());
    mbd::deform_vertices(m, scene.engine().model, &s, vector.view(), mbd::DeformKernel::kAvx2);
    const std::vector<fx::Vec3> laplacian_vector(s.jv_posed_laplacian.begin(), s.jv_posed_laplacian.end());
    for (int a = 0; a < 3; ++a) EXPECT_EQ(scalar.axis[a], vector.axis[a]) << p[0] << " " << p[1] << " " << p[2];
    EXPECT_EQ(laplacian_scalar, laplacian_vector) << p[0] << " " << p[1] << " " << p[2];
  }
}

// Both eq. (4) kernels hand over exactly the vertices whose balls turn
// differently, in ascending order, and leave them unwritten.
TEST(MetaballDeformKernel, HandsOverTheTurnedVerticesInOrder) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
#if defined(__x86_64__)
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(scene.pose(20, 120, 60));
  const metaballs::MetaballModel& m = scene.model();
  const metaballs::MetaballState& s = scene.state();
  std::vector<uint32_t> expected;
  for (uint32_t v = 0; v < m.vertex_count; ++v)
    if (!mbd::balls_turn_alike(m, s, v)) expected.push_back(v);
  ASSERT_FALSE(expected.empty());
  const auto take = [](void* context, uint32_t v) { static_cast<std::vector<uint32_t>*>(context)->push_back(v); };
  std::vector<uint32_t> by_scalar, by_vector;
  const mbd::TurnedVertices to_scalar{take, &by_scalar}, to_vector{take, &by_vector};
  DeformOutput scalar(m.vertex_count), vector(m.vertex_count);
  mbd::deform_normal_balls_scalar(m, s, scalar.view(), {}, 0, UINT32_MAX, &to_scalar);
  ASSERT_TRUE(mbd::deform_normal_balls_avx2(m, s, vector.view(), {}, 0, UINT32_MAX, &to_vector));
  EXPECT_EQ(by_scalar, expected);
  EXPECT_EQ(by_vector, expected);
  for (const uint32_t v : expected) {
    EXPECT_EQ(scalar.axis[0][v], 0x5A5A5A5A) << v;
    EXPECT_EQ(vector.axis[0][v], 0x5A5A5A5A) << v;
  }
  for (int a = 0; a < 3; ++a) EXPECT_EQ(scalar.axis[a], vector.axis[a]);
#endif
}

// More balls than the kernel widens: it declines and writes nothing.
TEST(MetaballDeformKernel, DeclinesModelsWithMoreBallsThanItWidens) {
  if (!avx2_deform_available()) GTEST_SKIP() << "no AVX2 on this CPU";
#if defined(__x86_64__)
  ArmScene scene;
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(scene.pose(0, 30, 0));
  metaballs::MetaballModel m = scene.model();
  std::vector<fx::Vec3> rest(300, fx::Vec3{0, 0, 0});
  m.vertex_count = 0;  // nothing to deform: only the ball count matters
  m.ball_rest = rest;
  DeformOutput out(1);
  EXPECT_FALSE(mbd::deform_normal_balls_avx2(m, scene.state(), out.view()));
  EXPECT_EQ(out.axis[0][0], 0x5A5A5A5A);
#endif
}

}  // namespace
}  // namespace sinew::test
