// The vector LBS kernel of this target (AVX2 on x86-64, NEON on aarch64)
// writes exactly the scalar specification's words and returns the same
// saturation count, on adversarial rigs: palette entries at and beyond the
// limits, saturating positions, zero and huge normals, zero, negative and
// oversized weights, every K from 1 to 8, counts and offsets that are not
// multiples of anything, mixed DQS vertices and random rigs (fixed seeds).
// Skipped where the CPU has no vector kernel (x86-64 without AVX2, armhf).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "sim_core/skin/skinning.hpp"
#include "tests/sim_core/skin/adversarial_skin_rig.hpp"

namespace {

using sinew::skin::LbsKernel;
namespace fx = sinew::fx;
namespace rig = sinew::rig;

// How a generated rig stresses the kernel: its palette here, its vertices in
// adversarial_skin_rig.hpp.
struct KernelCase {
  uint32_t k = 4;
  uint32_t vertices = 1000;
  uint32_t palette = 32;
  int linear_mode = 0;    // 0 random within +-64, 1 at the limits, 2 beyond +-64 (clamps), 3 rotations
  int weight_mode = 0;    // see VertexStress
  int position_mode = 0;  // see VertexStress
  int normal_mode = 0;    // see VertexStress (2: no normals)
  bool dual = false;      // some vertices DQS
};

using KernelRig = sinew_skin_test::AdversarialRig;
using sinew_skin_test::stress_pick;
using sinew_skin_test::stress_uniform;

void kernel_make_rig(const KernelCase& c, uint64_t seed, KernelRig* r) {
  std::mt19937_64 rng(seed);
  constexpr int64_t kL = int64_t{1} << 30;  // 64 in Q8.24, 1 in Q2.30
  for (uint32_t j = 0; j < c.palette; ++j) {
    fx::Mat34 m{};
    for (int i = 0; i < 3; ++i) {
      for (int e = 0; e < 3; ++e) {
        switch (c.linear_mode) {
          case 0:
            m.m[i][e] = stress_uniform(rng, -kL, kL);
            break;
          case 1:
            m.m[i][e] = stress_pick(rng, {-(1 << 30), 1 << 30, (1 << 30) - 1, -(1 << 30) + 1, 0});
            break;
          case 2:
            m.m[i][e] = stress_pick(rng, {INT32_MIN, INT32_MAX, 1 << 30, -(1 << 30), (1 << 30) + 1, 7});
            break;
          default:
            m.m[i][e] = i == e ? (1 << 24) : stress_uniform(rng, -(1 << 20), 1 << 20);
            break;
        }
      }
      m.t[i] = rng() % 3 == 0 ? stress_pick(rng, {INT32_MAX, -INT32_MAX, INT32_MIN, 0})
                              : stress_uniform(rng, INT32_MIN, INT32_MAX);
    }
    r->palette.push_back(m);
    fx::DualQuat d{};
    d.real = {stress_pick(rng, {1 << 30, -(1 << 30), 0}), 0, 0, 0};
    if (d.real.w == 0) d.real.x = 1 << 30;
    d.dual = {stress_uniform(rng, -(1 << 28), 1 << 28), stress_uniform(rng, -(1 << 28), 1 << 28),
              stress_uniform(rng, -(1 << 28), 1 << 28), stress_uniform(rng, -(1 << 28), 1 << 28)};
    r->dual.push_back(d);
  }
  const sinew_skin_test::VertexStress stress{.k = c.k,
                                             .vertices = c.vertices,
                                             .weight_mode = c.weight_mode,
                                             .position_mode = c.position_mode,
                                             .normal_mode = c.normal_mode,
                                             .method = static_cast<uint8_t>(rig::SkinMethod::kLinear),
                                             .other_method = static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion),
                                             .mixed = c.dual,
                                             .extreme_weights = {INT32_MAX, INT32_MIN + 1, (1 << 30) + 1}};
  sinew_skin_test::add_stress_vertices(stress, c.palette, c.dual, rng, r);
}

// The vector kernels this target builds: NEON on aarch64, else AVX2 and
// AVX-512 (each compared where the CPU has it; SetUp skips where none runs).
constexpr LbsKernel kVectorKernel =
#if defined(__aarch64__)
    LbsKernel::kNeon;
#else
    LbsKernel::kAvx2;
#endif
constexpr LbsKernel kVectorKernels[] = {
#if defined(__aarch64__)
    LbsKernel::kNeon,
#else
    LbsKernel::kAvx2,
    LbsKernel::kAvx512,
#endif
};

struct KernelOutput {
  std::vector<int32_t> position[3], normal[3];
  uint32_t saturated = 0;
};

KernelOutput kernel_run(LbsKernel kernel, const KernelRig& r, bool dual, bool normals, uint32_t first, uint32_t count) {
  KernelOutput o;
  sinew::skin::SkinnedVertices out;
  for (int i = 0; i < 3; ++i) {
    o.position[i].assign(count, 0x5A5A5A5A);
    o.normal[i].assign(count, 0x5A5A5A5A);
    out.position[i] = o.position[i];
    if (normals) out.normal[i] = o.normal[i];
  }
  const std::span<const fx::DualQuat> dual_palette =
      dual ? std::span<const fx::DualQuat>(r.dual) : std::span<const fx::DualQuat>();
  o.saturated = sinew::skin::skin_vertices(kernel, r.rig, r.palette, dual_palette, first, count, out);
  return o;
}

// Runs both kernels on [first, first + count) of a built rig and compares every word.
void kernel_expect_identical_rig(const KernelRig& r, bool dual, bool normals, uint32_t first, uint32_t count) {
  const KernelOutput want = kernel_run(LbsKernel::kScalar, r, dual, normals, first, count);
  for (const LbsKernel kernel : kVectorKernels) {
    if (!sinew::skin::lbs_kernel_supported(kernel)) continue;
    SCOPED_TRACE(sinew::skin::lbs_kernel_name(kernel));
    const KernelOutput got = kernel_run(kernel, r, dual, normals, first, count);
    EXPECT_EQ(got.saturated, want.saturated);
    for (int i = 0; i < 3; ++i) {
      for (uint32_t v = 0; v < count; ++v) {
        ASSERT_EQ(got.position[i][v], want.position[i][v]) << "position " << i << " of vertex " << first + v;
        ASSERT_EQ(got.normal[i][v], want.normal[i][v]) << "normal " << i << " of vertex " << first + v;
      }
    }
  }
}

// Builds the rig of a case and runs kernel_expect_identical_rig on it.
void kernel_expect_identical(const KernelCase& c, uint64_t seed, uint32_t first, uint32_t count) {
  KernelRig r;
  kernel_make_rig(c, seed, &r);
  SCOPED_TRACE(testing::Message() << "K=" << c.k << " palette=" << c.palette << " linear=" << c.linear_mode
                                  << " weights=" << c.weight_mode << " positions=" << c.position_mode
                                  << " normals=" << c.normal_mode << " dual=" << c.dual << " seed=" << seed
                                  << " first=" << first << " count=" << count);
  kernel_expect_identical_rig(r, c.dual, c.normal_mode != 2, first, count);
}

class SkinKernel : public testing::Test {
 protected:
  void SetUp() override {
    if (!sinew::skin::lbs_kernel_supported(kVectorKernel)) GTEST_SKIP() << "no vector LBS kernel on this CPU";
  }
};

TEST_F(SkinKernel, EveryKAndEveryStressMode) {
  uint64_t seed = 1;
  for (uint32_t k = 1; k <= 8; ++k)
    for (int lin = 0; lin < 4; ++lin)
      for (int w = 0; w < 4; ++w)
        for (int pos = 0; pos < 2; ++pos)
          for (int nor = 0; nor < 3; ++nor) {
            KernelCase c;
            c.k = k;
            c.vertices = 67;
            c.palette = 1 + static_cast<uint32_t>(seed % 40);
            c.linear_mode = lin;
            c.weight_mode = w;
            c.position_mode = pos;
            c.normal_mode = nor;
            c.dual = seed % 2 == 0;
            kernel_expect_identical(c, seed++, 0, c.vertices);
          }
}

TEST_F(SkinKernel, SaturationIsCountedTheSame) {
  KernelCase c;
  c.linear_mode = 2;
  c.weight_mode = 3;
  KernelRig r;
  kernel_make_rig(c, 99, &r);
  const KernelOutput want = kernel_run(LbsKernel::kScalar, r, false, true, 0, c.vertices);
  EXPECT_GT(want.saturated, 0u);  // the case really clamps
  kernel_expect_identical(c, 99, 0, c.vertices);
}

TEST_F(SkinKernel, CountsAndOffsetsNotMultiplesOfAnyWidth) {
  KernelCase c;
  c.vertices = 300;
  for (uint32_t count : {0u, 1u, 2u, 3u, 5u, 7u, 8u, 9u, 15u, 17u, 31u, 33u, 131u})
    for (uint32_t first : {0u, 1u, 3u, 7u, 100u}) kernel_expect_identical(c, 1000 + count, first, count);
}

TEST_F(SkinKernel, RandomRigs) {
  std::mt19937_64 rng(20240611);
  for (int i = 0; i < 200; ++i) {
    KernelCase c;
    c.k = 1 + static_cast<uint32_t>(rng() % 8);
    c.vertices = 1 + static_cast<uint32_t>(rng() % 500);
    c.palette = 1 + static_cast<uint32_t>(rng() % 300);  // also beyond the widened buffer
    c.linear_mode = static_cast<int>(rng() % 4);
    c.weight_mode = static_cast<int>(rng() % 4);
    c.position_mode = static_cast<int>(rng() % 2);
    c.normal_mode = static_cast<int>(rng() % 3);
    c.dual = rng() % 2 == 0;
    const uint32_t first = static_cast<uint32_t>(rng() % c.vertices);
    kernel_expect_identical(c, rng(), first, c.vertices - first);
  }
}

// Beyond AVX2's widened buffer (the scalar path there); NEON reads the palette in place.
TEST_F(SkinKernel, LargePaletteIdentically) {
  KernelCase c;
  c.palette = 4096;
  c.k = 8;
  kernel_expect_identical(c, 4096, 0, c.vertices);
}

// Halfway cases of every rounding shift, positive and negative, which random
// rigs almost never hit: weights that are multiples of a quarter on small
// linear entries and translations make the Q2.30 blend end in exactly one half
// about a quarter of the time, and positions and normals that are multiples
// of 2^23 make the Q8.24 products end in exactly one half about half the time.
TEST_F(SkinKernel, HalfwayCasesRoundLikeTheSpecification) {
  std::mt19937_64 rng(5);
  for (uint32_t k = 1; k <= 8; ++k) {
    KernelCase c;
    c.k = k;
    c.vertices = 259;
    c.palette = 9;
    KernelRig r;
    kernel_make_rig(c, 300 + k, &r);
    for (fx::Mat34& m : r.palette) {
      for (auto& row : m.m)
        for (int32_t& e : row) e = stress_uniform(rng, -7, 7);
      for (int32_t& t : m.t) t = stress_uniform(rng, -(1 << 27), 1 << 27);
    }
    for (int32_t& w : r.weight) w = stress_pick(rng, {1 << 29, -(1 << 29), 1 << 28, -(1 << 28), 3 << 28});
    for (int i = 0; i < 3; ++i)
      for (uint32_t v = 0; v < c.vertices; ++v) {
        r.position[i][v] = stress_uniform(rng, -255, 255) * (1 << 23);
        r.normal[i][v] = stress_uniform(rng, -255, 255) * (1 << 23);
      }
    SCOPED_TRACE(testing::Message() << "K=" << k);
    kernel_expect_identical_rig(r, false, true, 0, c.vertices);
  }
}

// Identity palette and one-hot weights pass rest normals through unchanged, so
// the renormalisation sees vectors of every magnitude from 1 LSB to int32 limits.
TEST_F(SkinKernel, NormalsOfEveryMagnitude) {
  for (uint32_t k : {1u, 3u, 8u}) {
    KernelCase c;
    c.k = k;
    c.vertices = 4000 + k;
    c.palette = 5;
    c.weight_mode = 1;
    KernelRig r;
    kernel_make_rig(c, 7 + k, &r);
    for (fx::Mat34& m : r.palette) m = fx::Mat34{{{1 << 24, 0, 0}, {0, 1 << 24, 0}, {0, 0, 1 << 24}}, {0, 0, 0}};
    std::mt19937_64 rng(k);
    for (uint32_t v = 0; v < c.vertices; ++v) {
      const int e = static_cast<int>(v % 32);
      for (int i = 0; i < 3; ++i) {
        const int64_t span = int64_t{1} << e;
        int64_t x = static_cast<int64_t>(rng() % static_cast<uint64_t>(2 * span + 1)) - span;
        if (rng() % 7 == 0) x = stress_pick(rng, {0, 1, -1, INT32_MAX, INT32_MIN});
        r.normal[i][v] = static_cast<int32_t>(std::clamp<int64_t>(x, INT32_MIN, INT32_MAX));
      }
    }
    SCOPED_TRACE(testing::Message() << "K=" << k);
    kernel_expect_identical_rig(r, false, true, 0, c.vertices);
  }
}

TEST_F(SkinKernel, DefaultIsTheVectorKernelWhereSupported) {
  // The widest kernel the CPU runs: AVX-512 over AVX2 on x86-64.
  const LbsKernel widest = kVectorKernel == LbsKernel::kAvx2 && sinew::skin::lbs_kernel_supported(LbsKernel::kAvx512)
                               ? LbsKernel::kAvx512
                               : kVectorKernel;
  EXPECT_EQ(sinew::skin::lbs_kernel_default(), widest);
  EXPECT_STREQ(sinew::skin::lbs_kernel_name(sinew::skin::lbs_kernel_default()), widest == LbsKernel::kNeon ? "neon"
                                                                                : widest == LbsKernel::kAvx512
                                                                                    ? "avx512"
                                                                                    : "avx2");
}

}  // namespace
