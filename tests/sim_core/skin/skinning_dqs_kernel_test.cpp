// The AVX2 DQS kernel writes exactly the scalar specification's words, on
// adversarial rigs: palette quaternions at and beyond the near-unit bound,
// antipodal and nearly antipodal pairs, dual parts at the int32 limits,
// saturating positions, zero and huge normals, zero, signed and extreme
// weights (sum |w| <= 2^31, where the scalar blend is defined), every K from
// 1 to 8, counts and offsets that are not multiples of four, LBS vertices
// mixed in, and random rigs (fixed seeds). Skipped where the CPU has no AVX2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "sim_core/skin/skinning.hpp"
#include "tests/sim_core/skin/adversarial_skin_rig.hpp"

namespace {

using sinew::skin::DqsKernel;
using sinew::skin::LbsKernel;
namespace fx = sinew::fx;
namespace rig = sinew::rig;

constexpr int32_t kDqsOne = int32_t{1} << 30;
constexpr int32_t kDqsNearUnitLimit = (1 << 30) + (1 << 28);  // skinning_detail.hpp's bound

// How a generated rig stresses the kernel: its palette here, its vertices in
// adversarial_skin_rig.hpp.
struct DqsCase {
  uint32_t k = 4;
  uint32_t vertices = 200;
  uint32_t palette = 24;
  int real_mode = 0;      // 0 random unit, 1 at the limits, 2 one entry beyond the bound, 3 antipodal pairs
  int dual_mode = 0;      // 0 rig-sized translations, 1 int32 extremes
  int weight_mode = 0;    // see VertexStress
  int position_mode = 0;  // see VertexStress
  int normal_mode = 0;    // see VertexStress (2: no normals)
  bool mixed = false;     // some vertices LBS
};

using DqsRig = sinew_skin_test::AdversarialRig;
using sinew_skin_test::stress_pick;
using sinew_skin_test::stress_uniform;

fx::Quat dqs_random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  double c[4], n = 0;
  do {
    n = 0;
    for (double& x : c) {
      x = g(rng);
      n += x * x;
    }
  } while (n < 1e-6);
  const double s = std::ldexp(1.0, 30) / std::sqrt(n);
  return {static_cast<int32_t>(std::lround(c[0] * s)), static_cast<int32_t>(std::lround(c[1] * s)),
          static_cast<int32_t>(std::lround(c[2] * s)), static_cast<int32_t>(std::lround(c[3] * s))};
}

fx::Quat dqs_negated(const fx::Quat& q) { return {-q.w, -q.x, -q.y, -q.z}; }

fx::Quat dqs_real(const DqsCase& c, uint32_t j, std::mt19937_64& rng, const std::vector<fx::DualQuat>& so_far) {
  switch (c.real_mode) {
    case 1: {
      const int32_t l = kDqsNearUnitLimit;
      fx::Quat q{};
      int32_t* comp[4] = {&q.w, &q.x, &q.y, &q.z};
      for (int32_t* x : comp) *x = stress_pick(rng, {l, -l, kDqsOne, -kDqsOne, 0, 1, -1, kDqsOne / 2});
      return q;
    }
    case 2:
      if (j == 0) return {kDqsNearUnitLimit + 1, 0, 0, 0};  // outside: the whole call takes the scalar loop
      if (j == 1) return {INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN};
      return dqs_random_unit(rng);
    case 3:
      // Antipodal (q, -q) and nearly antipodal pairs, and exact orthogonals:
      // hemisphere tests of both signs and of zero.
      if (j % 2 == 1 && !so_far.empty()) {
        fx::Quat q = dqs_negated(so_far.back().real);
        if (rng() % 2 == 0) q.w += stress_uniform(rng, -3, 3);
        return q;
      }
      if (rng() % 4 == 0) return {0, kDqsOne, 0, 0};
      return dqs_random_unit(rng);
    default:
      return dqs_random_unit(rng);
  }
}

void dqs_make_rig(const DqsCase& c, uint64_t seed, DqsRig* r) {
  std::mt19937_64 rng(seed);
  for (uint32_t j = 0; j < c.palette; ++j) {
    fx::DualQuat d{};
    d.real = dqs_real(c, j, rng, r->dual);
    int32_t* dual[4] = {&d.dual.w, &d.dual.x, &d.dual.y, &d.dual.z};
    for (int32_t* x : dual)
      *x = c.dual_mode == 0 ? stress_uniform(rng, -(1 << 24), 1 << 24)
                            : stress_pick(rng, {INT32_MAX, INT32_MIN, INT32_MIN + 1, 0, 1 << 30, -(1 << 30)});
    r->dual.push_back(d);
    r->palette.push_back(fx::Mat34{{{1 << 24, 0, 0}, {0, 1 << 24, 0}, {0, 0, 1 << 24}}, {0, 0, 0}});
  }
  const sinew_skin_test::VertexStress stress{.k = c.k,
                                             .vertices = c.vertices,
                                             .weight_mode = c.weight_mode,
                                             .position_mode = c.position_mode,
                                             .normal_mode = c.normal_mode,
                                             .method = static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion),
                                             .other_method = static_cast<uint8_t>(rig::SkinMethod::kLinear),
                                             .mixed = c.mixed,
                                             .extreme_weights = {INT32_MAX, INT32_MIN, -kDqsOne, kDqsOne}};
  sinew_skin_test::add_stress_vertices(stress, c.palette, true, rng, r);
}

struct DqsOutput {
  std::vector<int32_t> position[3], normal[3];
  uint32_t saturated = 0;
};

DqsOutput dqs_run(DqsKernel kernel, const DqsRig& r, bool normals, uint32_t first, uint32_t count) {
  DqsOutput o;
  sinew::skin::SkinnedVertices out;
  for (int i = 0; i < 3; ++i) {
    o.position[i].assign(count, 0x5A5A5A5A);
    o.normal[i].assign(count, 0x5A5A5A5A);
    out.position[i] = o.position[i];
    if (normals) out.normal[i] = o.normal[i];
  }
  o.saturated = sinew::skin::skin_vertices(LbsKernel::kScalar, kernel, r.rig, r.palette, r.dual, first, count, out);
  return o;
}

// The vector DQS kernels of x86-64, each compared where the CPU runs it.
constexpr DqsKernel kVectorDqsKernels[] = {DqsKernel::kAvx2, DqsKernel::kAvx512};

// Every supported vector kernel's words against the specification's.
void expect_kernels_match(const DqsRig& r, bool normals, uint32_t first, uint32_t count) {
  const DqsOutput want = dqs_run(DqsKernel::kScalar, r, normals, first, count);
  for (DqsKernel kernel : kVectorDqsKernels) {
    if (!sinew::skin::dqs_kernel_supported(kernel)) continue;
    const DqsOutput got = dqs_run(kernel, r, normals, first, count);
    SCOPED_TRACE(testing::Message() << "kernel " << sinew::skin::dqs_kernel_name(kernel));
    EXPECT_EQ(got.saturated, want.saturated);
    for (int i = 0; i < 3; ++i) {
      for (uint32_t v = 0; v < count; ++v) {
        ASSERT_EQ(got.position[i][v], want.position[i][v]) << "position " << i << " of vertex " << first + v;
        ASSERT_EQ(got.normal[i][v], want.normal[i][v]) << "normal " << i << " of vertex " << first + v;
      }
    }
  }
}

// Runs the DQS kernels on [first, first + count) and compares every word.
void dqs_expect_identical(const DqsCase& c, uint64_t seed, uint32_t first, uint32_t count) {
  DqsRig r;
  dqs_make_rig(c, seed, &r);
  SCOPED_TRACE(testing::Message() << "K=" << c.k << " palette=" << c.palette << " real=" << c.real_mode << " dual="
                                  << c.dual_mode << " weights=" << c.weight_mode << " positions=" << c.position_mode
                                  << " normals=" << c.normal_mode << " mixed=" << c.mixed << " seed=" << seed
                                  << " first=" << first << " count=" << count);
  expect_kernels_match(r, c.normal_mode != 2, first, count);
}

class SkinDqsKernel : public testing::Test {
 protected:
  void SetUp() override {
    if (!sinew::skin::dqs_kernel_supported(DqsKernel::kAvx2)) GTEST_SKIP() << "CPU without AVX2";
  }
};

TEST_F(SkinDqsKernel, EveryKAndEveryStressMode) {
  uint64_t seed = 1;
  for (uint32_t k = 1; k <= 8; ++k)
    for (int real = 0; real < 4; ++real)
      for (int dual = 0; dual < 2; ++dual)
        for (int w = 0; w < 4; ++w)
          for (int pos = 0; pos < 2; ++pos)
            for (int nor = 0; nor < 3; ++nor) {
              DqsCase c;
              c.k = k;
              c.vertices = 39;
              c.palette = 1 + static_cast<uint32_t>(seed % 40);
              c.real_mode = real;
              c.dual_mode = dual;
              c.weight_mode = w;
              c.position_mode = pos;
              c.normal_mode = nor;
              c.mixed = seed % 3 == 0;
              dqs_expect_identical(c, seed++, 0, c.vertices);
            }
}

TEST_F(SkinDqsKernel, CountsAndOffsetsNotMultiplesOfFour) {
  for (bool mixed : {false, true}) {
    DqsCase c;
    c.vertices = 300;
    c.mixed = mixed;
    for (uint32_t count : {0u, 1u, 2u, 3u, 5u, 6u, 7u, 9u, 13u, 31u, 131u})
      for (uint32_t first : {0u, 1u, 2u, 3u, 101u}) dqs_expect_identical(c, 2000 + count, first, count);
  }
}

// Weights that cancel (signed, or antipodal pairs) leave tiny or zero blended
// real parts: fx::normalize's division path and saturating dual parts.
TEST_F(SkinDqsKernel, DegenerateBlends) {
  DqsCase c;
  c.k = 2;
  c.palette = 2;
  c.vertices = 64;
  DqsRig r;
  dqs_make_rig(c, 5, &r);
  r.dual[0].real = {kDqsOne, 0, 0, 0};
  r.dual[1].real = {kDqsOne, 0, 0, 0};
  r.dual[1].dual = {INT32_MAX, INT32_MIN, INT32_MAX, 1 << 29};
  for (uint32_t v = 0; v < c.vertices; ++v) {
    r.joint[2 * v] = 0;
    r.joint[2 * v + 1] = 1;
    r.weight[2 * v] = static_cast<int32_t>(v) << 20;  // equal and opposite at v = 0, tiny sums near it
    r.weight[2 * v + 1] = -(static_cast<int32_t>(v % 7) << 20);
  }
  expect_kernels_match(r, true, 0, c.vertices);
}

TEST_F(SkinDqsKernel, RandomRigs) {
  std::mt19937_64 rng(20261124);
  for (int i = 0; i < 300; ++i) {
    DqsCase c;
    c.k = 1 + static_cast<uint32_t>(rng() % 8);
    c.vertices = 1 + static_cast<uint32_t>(rng() % 400);
    c.palette = 1 + static_cast<uint32_t>(rng() % 300);
    c.real_mode = static_cast<int>(rng() % 4);
    c.dual_mode = static_cast<int>(rng() % 2);
    c.weight_mode = static_cast<int>(rng() % 4);
    c.position_mode = static_cast<int>(rng() % 2);
    c.normal_mode = static_cast<int>(rng() % 3);
    c.mixed = rng() % 2 == 0;
    const uint32_t first = static_cast<uint32_t>(rng() % c.vertices);
    dqs_expect_identical(c, rng(), first, c.vertices - first);
  }
}

// Runs of vertices with weight 1 on one entry (the kernels' rigid runs,
// four or eight in a row, aligned or not), broken by vertices that look rigid but
// are not (another weight nonzero, or weight 1 on a different entry), with
// an entry of zero real part (normalize_fast's division path) and dual
// parts at the int32 limits (|t| beyond 2^61, where the position's adds
// could saturate: the kernel must refuse those entries).
TEST_F(SkinDqsKernel, RigidRunsOfOneEntry) {
  uint64_t seed = 77;
  for (uint32_t k = 1; k <= 4; ++k)
    for (int real = 0; real < 4; ++real)
      for (int dual = 0; dual < 2; ++dual)
        for (int pos = 0; pos < 2; ++pos)
          for (int nor = 0; nor < 3; ++nor) {
            DqsCase c;
            c.k = k;
            c.vertices = 96;
            c.palette = 6;
            c.real_mode = real == 2 ? 0 : real;  // mode 2 sends the whole call to the scalar loop
            c.dual_mode = dual;
            c.position_mode = pos;
            c.normal_mode = nor;
            c.mixed = seed % 3 == 0;
            DqsRig r;
            dqs_make_rig(c, seed, &r);
            if (real == 2) r.dual[5].real = {0, 0, 0, 0};
            for (uint32_t v = 0; v < c.vertices; ++v) {
              const uint32_t run = v / 20;  // holds runs of four and of eight between the breaks
              for (uint32_t i = 0; i < k; ++i) {
                r.joint[v * k + i] = static_cast<uint16_t>((run + i) % c.palette);
                r.weight[v * k + i] = i == 0 ? kDqsOne : 0;
              }
              if (v % 13 == 12 && k > 1) r.weight[v * k + 1] = 1 << 20;                         // not rigid
              if (v % 17 == 16) r.joint[v * k] = static_cast<uint16_t>((run + 1) % c.palette);  // another entry
            }
            const bool normals = nor != 2;
            for (uint32_t first : {0u, 1u, 3u}) {
              const uint32_t count = c.vertices - first;
              SCOPED_TRACE(testing::Message() << "K=" << k << " real=" << real << " dual=" << dual
                                              << " positions=" << pos << " normals=" << nor << " first=" << first);
              expect_kernels_match(r, normals, first, count);
            }
            ++seed;
          }
}

TEST_F(SkinDqsKernel, DefaultIsTheWidestSupported) {
  const bool wide = sinew::skin::dqs_kernel_supported(DqsKernel::kAvx512);
  EXPECT_EQ(sinew::skin::dqs_kernel_default(), wide ? DqsKernel::kAvx512 : DqsKernel::kAvx2);
  EXPECT_STREQ(sinew::skin::dqs_kernel_name(sinew::skin::dqs_kernel_default()), wide ? "avx512" : "avx2");
}

}  // namespace
