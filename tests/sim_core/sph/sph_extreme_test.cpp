// An SPH joint at the limits sph_validate accepts: particles, skin and load
// point at +-(2^31 - 1), a flexion axis along the diagonal (so a particle's
// offset along it reaches sqrt(3) x 2^31), every gain at the top of its
// range, kernel radii of one LSB and of INT32_MAX, and transforms at the
// Lin / Len extremes. The sanitizer builds abort on signed overflow; the
// bend and the skin offsets must also come out the same from a second run.
#include <gtest/gtest.h>

#include <climits>
#include <vector>

#include "sim_core/sph/sph_state.hpp"
#include "sim_core/sph/sph_step.hpp"

namespace sph = sinew::sph;
namespace fx = sinew::fx;

namespace {

constexpr int32_t kDiagonal = 619925131;  // 2^30 / sqrt(3), rounded: a unit axis (1, 1, 1) / sqrt(3)

struct ExtremeJoint {
  static constexpr uint32_t kParticles = 32, kSkin = 8;
  std::vector<fx::Len> local[3], skin[3];
  std::vector<uint8_t> bone;
  std::vector<uint32_t> skin_vertex;
  sph::SphModel model;

  explicit ExtremeJoint(fx::Len h) {
    for (int a = 0; a < 3; ++a) {
      for (uint32_t i = 0; i < kParticles; ++i) local[a].push_back(((i >> a) & 1) ? INT32_MAX : INT32_MIN);
      for (uint32_t v = 0; v < kSkin; ++v) skin[a].push_back(((v >> a) & 1) ? INT32_MIN : INT32_MAX);
    }
    for (uint32_t i = 0; i < kParticles; ++i) bone.push_back(static_cast<uint8_t>(i % 2 == 0 ? 1 : (i / 8) % 2));
    for (uint32_t v = 0; v < kSkin; ++v) skin_vertex.push_back(v);
    sph::SphParams& p = model.params;
    p.h = h;
    p.grid_radius = h == INT32_MAX ? INT32_MAX : 32 * h;
    p.substeps = sph::kMaxSubsteps;
    p.max_neighbours = sph::kMaxNeighbours;
    p.elastic_gain = p.pressure_gain = p.viscosity_gain = fx::kUnitOne - 1;
    p.damping = fx::kUnitOne;
    p.load_gain = INT32_MAX;
    p.tau_f = 1;
    p.yield_count = kParticles;
    model.joint = {0, 1, {kDiagonal, kDiagonal, kDiagonal}, {INT32_MAX, INT32_MIN, INT32_MAX}};
    for (int a = 0; a < 3; ++a) {
      model.rest_local[a] = local[a];
      model.rest_model[a] = local[a];
      model.skin_rest[a] = skin[a];
    }
    model.bone = bone;
    model.skin_vertex = skin_vertex;
  }
};

fx::Mat34 transform(int32_t lin, int32_t t) {
  fx::Mat34 m{};
  for (int r = 0; r < 3; ++r) {
    m.m[r][r] = lin;
    m.t[r] = t;
  }
  return m;
}

std::vector<int32_t> run(fx::Len h) {
  ExtremeJoint j(h);
  EXPECT_TRUE(sph::sph_validate_model(j.model).ok()) << sph::sph_validate_model(j.model).message;
  std::vector<uint64_t> arena(sph::sph_state_bytes(j.model) / 8 + 1);
  const std::vector<fx::Mat34> rest = {transform(fx::kLinOne, 0), transform(fx::kLinOne, 0)};
  sph::SphState st;
  const sph::LayerStatus init = sph::sph_init(j.model, rest, arena.data(), arena.size() * 8, &st);
  EXPECT_TRUE(init.ok()) << init.message;
  if (!init.ok()) return {};
  std::vector<int32_t> out;
  const int32_t lins[] = {fx::kLinOne, INT32_MAX, INT32_MIN, 1 << 30, -(1 << 30), 0};
  const int32_t ts[] = {0, INT32_MAX, INT32_MIN};
  const int32_t forces[] = {1 << 30, -(1 << 30), 0};
  for (int32_t lin : lins)
    for (int32_t t : ts)
      for (int32_t f : forces) {
        const std::vector<fx::Mat34> pose = {transform(lin, t), transform(fx::neg_sat(lin), fx::neg_sat(t))};
        sph::SphInputs in;
        in.transforms = pose;
        in.force = {f, fx::neg_sat(f), f};
        const sph::LayerStatus s = sph::sph_step(&st, in);
        EXPECT_TRUE(s.ok()) << s.message;
        out.push_back(static_cast<int32_t>(st.bend));
        for (int a = 0; a < 3; ++a) out.insert(out.end(), st.skin_offset[a].begin(), st.skin_offset[a].end());
      }
  return out;
}

}  // namespace

TEST(SphExtremes, NarrowKernelAtTheLimitsRunsDefined) { EXPECT_EQ(run(1), run(1)); }

TEST(SphExtremes, WideKernelAtTheLimitsRunsDefined) { EXPECT_EQ(run(INT32_MAX), run(INT32_MAX)); }
