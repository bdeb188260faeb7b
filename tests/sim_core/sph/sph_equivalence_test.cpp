// The optimised sph step against the first implementation kept in
// sph_reference_v1 (per-particle neighbour lists, both sides of every pair):
// same model, same inputs, and after every step every persistent state word
// (positions, velocities, ideal positions, accelerations / displacements,
// densities, pressures, inverse densities, yield flags,
// skin weights and offsets, bend, joint yield, flexed transform, inertia,
// and the step statistics) must be equal. Only the per-substep
// scratch of the neighbour search (grid, lists) differs in layout and is not
// compared. Cases: the arm's elbow, random tissues with dense clusters (lists
// overflowing max_neighbours), particles on cell borders, a kernel radius
// whose offsets round on exact halves (asymmetric pairs), particles that yield,
// and the extremes sph_validate accepts.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <string>
#include <vector>

#include "host_tools/determinism/split_mix.hpp"
#include "host_tools/layers/sph/sph_reference_v1.hpp"
#include "sim_core/fixed/quat.hpp"
#include "sph_fixture.hpp"

namespace sph = sinew::sph;
namespace fx = sinew::fx;
namespace ref = sinew::sph_reference_v1;

namespace {

template <typename A, typename B>
::testing::AssertionResult same_words(const char* what, const A& a, const B& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << what << ": sizes " << a.size() << " vs " << b.size();
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i])
      return ::testing::AssertionFailure()
             << what << "[" << i << "]: " << int64_t{a[i]} << " vs reference " << int64_t{b[i]};
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult equivalent_states(const sph::SphState& s, const ref::RefState& r) {
  ::testing::AssertionResult ok = ::testing::AssertionSuccess();
  const auto check = [&ok](::testing::AssertionResult res) {
    if (ok && !res) ok = res;
  };
  for (int a = 0; a < 3; ++a) {
    check(same_words("position", s.position[a], r.position[a]));
    check(same_words("velocity", s.velocity[a], r.velocity[a]));
    check(same_words("ideal", s.ideal[a], r.ideal[a]));
    check(same_words("scratch", s.scratch[a], r.scratch[a]));
    check(same_words("skin_offset", s.skin_offset[a], r.skin_offset[a]));
  }
  check(same_words("pressure", s.pressure, r.pressure));
  check(same_words("yielded", s.yielded, r.yielded));
  check(same_words("density", s.density, r.density));
  check(same_words("rest_density", s.rest_density, r.rest_density));
  check(same_words("inv_density", s.inv_density, r.inv_density));
  check(same_words("skin_particle", s.skin_particle, r.skin_particle));
  check(same_words("skin_weight", s.skin_weight, r.skin_weight));
  check(same_words("skin_count", s.skin_count, r.skin_count));
  const int64_t scalars[][2] = {
      {static_cast<int64_t>(s.bend), static_cast<int64_t>(r.bend)},
      {s.joint_yielded, r.joint_yielded},
      {s.yielded_particles, r.yielded_particles},
      {s.grid_dim, r.grid_dim},
      {s.inertia_q12, r.inertia_q12},
      {s.yield_torque_q12, r.yield_torque_q12},
      {static_cast<int64_t>(s.stats.steps), static_cast<int64_t>(r.stats.steps)},
      {s.stats.neighbour_overflow, r.stats.neighbour_overflow},
      {s.stats.max_neighbour_count, r.stats.max_neighbour_count},
      {static_cast<int64_t>(s.stats.neighbour_pairs), static_cast<int64_t>(r.stats.neighbour_pairs)},
      {s.stats.saturated, r.stats.saturated},
  };
  const char* names[] = {"bend",           "joint_yielded",         "yielded_particles", "grid_dim",
                         "inertia",        "yield_torque",          "stats.steps",       "stats.neighbour_overflow",
                         "stats.max_list", "stats.neighbour_pairs", "stats.saturated"};
  for (size_t k = 0; k < sizeof scalars / sizeof scalars[0]; ++k)
    if (ok && scalars[k][0] != scalars[k][1])
      ok = ::testing::AssertionFailure() << names[k] << ": " << scalars[k][0] << " vs reference " << scalars[k][1];
  for (int row = 0; row < 3 && ok; ++row) {
    for (int c = 0; c < 3; ++c)
      if (s.distal_flexed.m[row][c] != r.distal_flexed.m[row][c])
        ok = ::testing::AssertionFailure() << "distal_flexed.m";
    if (s.distal_flexed.t[row] != r.distal_flexed.t[row]) ok = ::testing::AssertionFailure() << "distal_flexed.t";
  }
  return ok;
}

// Both implementations on one model: init, then `poses.size()` steps.
struct Pair {
  std::vector<uint64_t> arena;
  sph::SphState state;
  ref::RefState reference;
};

// A synthetic joint: particles and skin vertices drawn by `place` around the
// origin, bones alternating in runs, transforms chosen per step by the caller.
struct RandomJoint {
  std::vector<fx::Len> local[3], skin[3];
  std::vector<uint8_t> bone;
  std::vector<uint32_t> skin_vertex;
  sph::SphModel model;
};

fx::Mat34 rotation_about(fx::Vec3 axis, fx::Angle angle, fx::Vec3 t) {
  return fx::mat34_from_quat(fx::quat_from_axis_angle(axis, angle), t);
}

fx::Mat34 scaled(int32_t lin, int32_t t) {
  fx::Mat34 m{};
  for (int r = 0; r < 3; ++r) {
    m.m[r][r] = lin;
    m.t[r] = t;
  }
  return m;
}

// Runs `steps` steps of both implementations with poses and forces from
// `rng`, comparing after init and after each step. Returns the number of
// steps in which some list overflowed max_neighbours (the truncation path)
// through `overflow_steps`.
// Also counts, through `half_pairs`, the pairs whose sides were found by
// the two-sided search with an axis rounded on an exact half.
void run_both(const sph::SphModel& model, const std::vector<fx::Mat34>& rest, int steps, uint64_t seed,
              bool extreme_poses, uint32_t* overflow_steps, uint32_t* yielded, uint32_t* half_pairs = nullptr) {
  ASSERT_TRUE(sph::sph_validate_model(model).ok()) << sph::sph_validate_model(model).message;
  Pair p;
  p.arena.assign(sph::sph_state_bytes(model) / 8 + 1, 0);
  ASSERT_TRUE(sph::sph_init(model, rest, p.arena.data(), p.arena.size() * 8, &p.state).ok());
  ASSERT_TRUE(ref::ref_init(model, rest, &p.reference).ok());
  ASSERT_TRUE(equivalent_states(p.state, p.reference)) << "after init";
  sinew::determinism::SplitMix64 rng(seed);
  const fx::Vec3 axis = model.joint.axis;
  for (int t = 0; t < steps; ++t) {
    std::vector<fx::Mat34> pose = rest;
    if (extreme_poses) {
      const int32_t lins[] = {fx::kLinOne, INT32_MAX, INT32_MIN, 1 << 30, -(1 << 30), 0};
      const int32_t ts[] = {0, INT32_MAX, INT32_MIN, rng.next_i32()};
      const int32_t lin = lins[rng.next_u32() % 6], tr = ts[rng.next_u32() % 4];
      pose[model.joint.proximal_joint] = scaled(lin, tr);
      pose[model.joint.distal_joint] = scaled(fx::neg_sat(lin), fx::neg_sat(tr));
    } else {
      // The distal bone swings about the axis by up to +-45 degrees.
      const fx::Mat34 flex = rotation_about(axis, static_cast<fx::Angle>(rng.range(-(1 << 29), 1 << 29)), {0, 0, 0});
      pose[model.joint.distal_joint] = fx::mul(rest[model.joint.distal_joint], flex);
    }
    sph::SphInputs in;
    in.transforms = pose;
    const int32_t f = rng.range(-(1 << 30), 1 << 30);
    in.force = {f, fx::neg_sat(f) / 2, rng.range(-(1 << 24), 1 << 24)};
    in.tresca = (t % 7) != 3;
    const sph::LayerStatus a = sph::sph_step(&p.state, in);
    const sph::LayerStatus b = ref::ref_step(&p.reference, in);
    ASSERT_EQ(a.ok(), b.ok());
    ASSERT_TRUE(equivalent_states(p.state, p.reference)) << "after step " << t;
    *yielded = std::max(*yielded, p.state.yielded_particles);
    if (p.state.stats.neighbour_overflow != 0) ++*overflow_steps;
    if (half_pairs != nullptr)
      for (uint32_t k = 0; k < p.state.pair_count; ++k)
        if (p.state.pairs[k].half != 0 && p.state.pairs[k].sides == 3) ++*half_pairs;
    if (t % 40 == 39) {  // also the reset path
      ASSERT_TRUE(sph::sph_reset(&p.state, pose).ok());
      ASSERT_TRUE(ref::ref_reset(&p.reference, pose).ok());
      ASSERT_TRUE(equivalent_states(p.state, p.reference)) << "after reset at step " << t;
    }
  }
}

enum class Layout { kUniform, kClusters, kCellBorders };

void make_joint(RandomJoint* j, uint32_t n, uint32_t skin, fx::Len h, fx::Len grid_radius, Layout layout, uint64_t seed,
                uint32_t max_neighbours = 24) {
  sinew::determinism::SplitMix64 rng(seed);
  // Some particles fall outside the grid (clamped); the range stays in Len.
  const int64_t span = std::min<int64_t>(grid_radius + 2 * int64_t{h}, INT32_MAX);
  const auto draw = [&](int a, uint32_t i) -> fx::Len {
    (void)a;
    switch (layout) {
      case Layout::kUniform:
        return static_cast<fx::Len>(rng.range(static_cast<int32_t>(-span / 2), static_cast<int32_t>(span / 2)));
      case Layout::kClusters: {
        // Eight tight clusters: every particle of a cluster within h / 8.
        const int64_t c = (static_cast<int64_t>(i % 8) - 4) * h / 2;
        return static_cast<fx::Len>(c + rng.range(-(h / 16), h / 16));
      }
      case Layout::kCellBorders: {
        // Exactly on a cell boundary of the grid (centre 0), or one LSB off.
        const int64_t k = rng.range(0, static_cast<int32_t>(2 * grid_radius / h));
        return static_cast<fx::Len>(-int64_t{grid_radius} + k * h + rng.range(-1, 1));
      }
    }
    return 0;
  };
  for (uint32_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) j->local[a].push_back(draw(a, i));
  for (uint32_t v = 0; v < skin; ++v)
    for (int a = 0; a < 3; ++a) j->skin[a].push_back(draw(a, v));
  for (uint32_t i = 0; i < n; ++i) j->bone.push_back(static_cast<uint8_t>((i / 3) % 2 == 0 || i == 0 ? 1 : 0));
  for (uint32_t v = 0; v < skin; ++v) j->skin_vertex.push_back(v);
  sph::SphParams& p = j->model.params;
  p.h = h;
  p.grid_radius = grid_radius;
  p.substeps = 2;
  p.max_neighbours = max_neighbours;
  p.elastic_gain = fx::kUnitOne / 50;
  p.pressure_gain = fx::kUnitOne / 20;
  p.viscosity_gain = fx::kUnitOne / 10;
  p.damping = fx::kUnitOne - fx::kUnitOne / 100;
  p.load_gain = fx::kUnitOne / 4;
  p.tau_f = sph::kDensOne / 8;  // low: particles yield
  p.yield_count = n / 4 + 1;
  // The load 4 h out along y (clamped into the Len range).
  const fx::Len reach = static_cast<fx::Len>(std::min<int64_t>(4 * int64_t{h}, INT32_MAX));
  j->model.joint = {0, 1, {0, 0, fx::kUnitOne}, {h, reach, 0}};
  for (int a = 0; a < 3; ++a) {
    j->model.rest_local[a] = j->local[a];
    j->model.rest_model[a] = j->local[a];
    j->model.skin_rest[a] = j->skin[a];
  }
  j->model.bone = j->bone;
  j->model.skin_vertex = j->skin_vertex;
}

const std::vector<fx::Mat34> kIdentityRest = {scaled(fx::kLinOne, 0), scaled(fx::kLinOne, 0)};

}  // namespace

TEST(SphEquivalence, ArmElbowMatchesReferenceEveryTick) {
  for (uint32_t particles : {200u, 1000u}) {
    sinew::layers::SphBuildOptions options;
    options.particle_count = particles;
    sinew::test::SphArm arm(options);
    ASSERT_TRUE(arm.ok()) << arm.error();
    ref::RefState reference;
    // The reference starts from the same rest pose the fixture initialised with.
    ASSERT_TRUE(ref::ref_init(arm.model(), arm.engine().model, &reference).ok());
    ASSERT_TRUE(equivalent_states(arm.state(), reference)) << "after init";
    const int elbow = arm.input("elbow.0");
    ASSERT_GE(elbow, 0);
    uint32_t most_yielded = 0;
    for (int t = 0; t < 240; ++t) {
      const int32_t phase = t % 160;
      arm.inputs()[static_cast<size_t>(elbow)] = (phase < 80 ? phase : 160 - phase) * (int32_t{1} << 23);
      const double fy = t < 160 ? 40.0 * (t + 1) / 160 : 0.0;
      ASSERT_TRUE(arm.tick(((t % 64) - 32) * 0.2, fy, 0).ok());
      sph::SphInputs in;
      in.transforms = arm.engine().model;
      in.force = {sinew::test::SphArm::newtons(((t % 64) - 32) * 0.2), sinew::test::SphArm::newtons(fy), 0};
      in.tresca = true;
      ASSERT_TRUE(ref::ref_step(&reference, in).ok());
      ASSERT_TRUE(equivalent_states(arm.state(), reference)) << particles << " particles, tick " << t;
      most_yielded = std::max(most_yielded, arm.state().yielded_particles);
    }
    EXPECT_GT(most_yielded, 0u) << "the workload should reach the Tresca yield";
  }
}

TEST(SphEquivalence, RandomTissuesMatchReference) {
  struct Case {
    const char* name;
    uint32_t n;
    fx::Len h;
    fx::Len grid_radius;
    Layout layout;
    uint32_t max_neighbours;
  };
  // 715827883 = 2^31 / 3 rounded: 2^50 / h rounds to 3 x 2^19, so every odd
  // offset lands on an exact half in pair_geometry's rounding (d_ji != -d_ij).
  // Lists of 24 overflow in the dense cases (the ordered path), not in the
  // sparse ones; 96 keeps most of the half-tie tissue on the two-sided path.
  const Case cases[] = {
      {"uniform", 600, 1 << 20, 6 << 20, Layout::kUniform, 24},
      {"clusters", 400, 1 << 20, 4 << 20, Layout::kClusters, 24},
      {"cell borders", 500, 1 << 20, 5 << 20, Layout::kCellBorders, 24},
      {"half ties", 300, 715827883, 715827883, Layout::kUniform, 96},
      {"half ties, short lists", 400, 715827883, 715827883, Layout::kUniform, 24},
      {"half ties on borders", 300, 715827883, 715827883, Layout::kCellBorders, 96},
      {"half ties, clusters", 160, 715827883, 715827883, Layout::kClusters, 96},
      {"odd h", 500, 999983, 5 * 999983, Layout::kUniform, 24},
      {"odd h clusters", 300, 999983, 3 * 999983, Layout::kClusters, 24},
  };
  uint32_t overflow_steps = 0, yielded_total = 0, half_pairs = 0;
  for (uint64_t seed = 1; seed <= 2; ++seed)
    for (const Case& c : cases) {
      SCOPED_TRACE(std::string(c.name) + " seed " + std::to_string(seed));
      RandomJoint j;
      make_joint(&j, c.n, 64, c.h, c.grid_radius, c.layout, seed * 7919 + c.n, c.max_neighbours);
      uint32_t yielded = 0;
      run_both(j.model, kIdentityRest, 60, seed, false, &overflow_steps, &yielded, &half_pairs);
      yielded_total += yielded;
      if (HasFatalFailure()) return;
    }
  // The cases must exercise the truncation, the yield and the two-sided
  // pairs with an exact half, or they prove less.
  EXPECT_GT(overflow_steps, 0u);
  EXPECT_GT(yielded_total, 0u);
  EXPECT_GT(half_pairs, 0u);
}

TEST(SphEquivalence, ExtremesMatchReference) {
  // Particles and skin at +-(2^31 - 1) and random, kernel radii of one LSB
  // and of INT32_MAX, every gain at the top of its range, the transforms at
  // the Lin / Len extremes.
  for (fx::Len h : {fx::Len{1}, fx::Len{INT32_MAX}, fx::Len{1 << 28}}) {
    SCOPED_TRACE("h " + std::to_string(h));
    RandomJoint j;
    const fx::Len radius = h == INT32_MAX ? INT32_MAX : (h == 1 ? 32 : 4 * h);
    make_joint(&j, 96, 16, h, radius, Layout::kUniform, static_cast<uint64_t>(h));
    sinew::determinism::SplitMix64 rng(static_cast<uint64_t>(h) + 5);
    for (uint32_t i = 0; i < 96; ++i)
      for (int a = 0; a < 3; ++a)
        if (i % 3 == 0)
          j.local[a][i] = ((i >> a) & 1) ? INT32_MAX : INT32_MIN;
        else if (i % 3 == 1)
          j.local[a][i] = rng.next_i32();
    sph::SphParams& p = j.model.params;
    p.substeps = sph::kMaxSubsteps;
    p.max_neighbours = sph::kMaxNeighbours;
    p.elastic_gain = p.pressure_gain = p.viscosity_gain = fx::kUnitOne - 1;
    p.damping = fx::kUnitOne;
    p.load_gain = INT32_MAX;
    p.tau_f = 1;
    j.model.joint.axis = {619925131, 619925131, 619925131};
    j.model.joint.load_point = {INT32_MAX, INT32_MIN, INT32_MAX};
    uint32_t overflow_steps = 0, yielded = 0;
    run_both(j.model, kIdentityRest, 24, 99, true, &overflow_steps, &yielded);
    if (HasFatalFailure()) return;
  }
}
