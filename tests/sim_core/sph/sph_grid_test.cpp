// The search through its candidate pairs (sph_grid.hpp), on one thread and
// over the workers, against the full half-stencil search on one thread,
// substep by substep, on the arm's particles moved the ways a list must survive or notice: small moves that
// add up past the slack, the whole tissue carried with the grid centre (the
// arm's own motion, which must not rebuild the list), a turn about the
// centre, and particles teleported. Every configuration must give the same
// pairs (whichever particle a pair lists first), neighbour counts and
// density sums; and the list must have been both reused and rebuilt, or the
// comparison says nothing about the reuse.
#include "sim_core/sph/sph_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

#include "host_tools/determinism/split_mix.hpp"
#include "sph_fixture.hpp"
#include "tests/support/test_workers.hpp"

namespace sph = sinew::sph;
namespace fx = sinew::fx;

namespace sph_grid_test {

// One pair as seen from its lower particle: (lo, hi, sides, s_lo, s_hi, d from lo).
using PairKey = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t, uint32_t, int32_t, int32_t, int32_t>;

struct SearchResult {
  std::vector<PairKey> pairs;
  std::vector<uint16_t> count;
  std::vector<int64_t> density;
};

PairKey key_of(const sph::SphPair& e) {
  if (e.a < e.b) return {e.a, e.b, e.sides, e.s_ab, e.s_ba, e.d[0], e.d[1], e.d[2]};
  // From b's side: each axis negated, one LSB up where it rounded on a half.
  const uint32_t sides = ((e.sides & 1u) << 1) | ((e.sides >> 1) & 1u);
  return {e.b,
          e.a,
          sides,
          e.s_ba,
          e.s_ab,
          -e.d[0] + static_cast<int32_t>(e.half & 1u),
          -e.d[1] + static_cast<int32_t>((e.half >> 1) & 1u),
          -e.d[2] + static_cast<int32_t>((e.half >> 2) & 1u)};
}

SearchResult result_of(const sph::SphState& st) {
  SearchResult r;
  if (st.gathered) {
    // Each particle's run of pairs as a (search over the workers).
    for (uint32_t i = 0; i < st.model->particle_count(); ++i)
      for (uint32_t k = st.run_first[i]; k < st.run_first[i] + st.run_count[i]; ++k)
        r.pairs.push_back(key_of(st.pairs[k]));
  } else {
    for (uint32_t k = 0; k < st.pair_count; ++k) r.pairs.push_back(key_of(st.pairs[k]));
  }
  std::sort(r.pairs.begin(), r.pairs.end());
  r.count.assign(st.neighbour_count.begin(), st.neighbour_count.end());
  r.density.assign(st.density_sum.begin(), st.density_sum.end());
  return r;
}

// The search as it runs (through the candidates, on one thread or over the
// workers), then the full search on one thread on the same positions (the
// candidates paused for it, then restored).
void expect_same_search(sph::SphState* st, fx::Vec3 centre, const sinew::layer::Workers* workers, const char* what,
                        int step) {
  sph::build_neighbours(st, centre, workers);
  EXPECT_EQ(st->gathered, workers != nullptr) << what << ", step " << step;
  const SearchResult listed = result_of(*st);
  const uint32_t pause = st->candidate_pause;
  st->candidate_pause = 2;  // build_neighbours takes one: the full search runs
  sph::build_neighbours(st, centre);
  st->candidate_pause = pause;
  const SearchResult full = result_of(*st);
  EXPECT_FALSE(full.pairs.empty());
  EXPECT_EQ(listed.pairs, full.pairs) << what << ", step " << step;
  EXPECT_EQ(listed.count, full.count) << what << ", step " << step;
  EXPECT_EQ(listed.density, full.density) << what << ", step " << step;
}

void run_moves(const sinew::layer::Workers* workers) {
  sinew::test::SphArm arm(sinew::layers::SphBuildOptions{});
  ASSERT_TRUE(arm.ok()) << arm.error();
  sph::SphState& st = arm.state();
  const uint32_t n = st.model->particle_count();
  const int64_t h = st.model->params.h;
  int64_t sum[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < n; ++i) sum[a] += st.position[a][i];
  fx::Vec3 centre{static_cast<int32_t>(sum[0] / n), static_cast<int32_t>(sum[1] / n), static_cast<int32_t>(sum[2] / n)};
  sinew::determinism::SplitMix64 rng(20261203);
  const auto jitter = [&](int32_t reach) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = 0; i < n; ++i) st.position[a][i] += rng.range(-reach, reach);
  };
  st.candidates_valid = false;
  uint32_t builds = 0, steps = 0;
  const auto step = [&](const char* what) {
    const uint32_t before = st.stats.candidate_builds;
    expect_same_search(&st, centre, workers, what, static_cast<int>(steps));
    builds += st.stats.candidate_builds - before;
    ++steps;
  };
  // Small moves (up to h / 64 an axis a step): they add up past the slack.
  for (int s = 0; s < 40; ++s) {
    jitter(static_cast<int32_t>(h / 64));
    step("small moves");
  }
  // The tissue carried with the grid centre by 3 h a step: no rebuild needed.
  const uint32_t before_carry = st.stats.candidate_builds;
  for (int s = 0; s < 10; ++s) {
    const int32_t dx = static_cast<int32_t>(3 * h), dy = static_cast<int32_t>(-2 * h);
    for (uint32_t i = 0; i < n; ++i) st.position[0][i] += dx, st.position[1][i] += dy;
    centre.x += dx, centre.y += dy;
    step("carried with the centre");
  }
  EXPECT_EQ(st.stats.candidate_builds, before_carry) << "a rigid carry with the centre rebuilt the list";
  // A turn about the centre, 2 degrees a step (about z).
  for (int s = 0; s < 10; ++s) {
    const double c = 0.99939082701909576, si = 0.034899496702500969;
    for (uint32_t i = 0; i < n; ++i) {
      const double x = st.position[0][i] - centre.x, y = st.position[1][i] - centre.y;
      st.position[0][i] = centre.x + static_cast<int32_t>(std::llround(c * x - si * y));
      st.position[1][i] = centre.y + static_cast<int32_t>(std::llround(si * x + c * y));
    }
    step("turned about the centre");
  }
  // Teleports: two particles swap places (each moves far, the set barely).
  for (int s = 0; s < 5; ++s) {
    const uint32_t i = static_cast<uint32_t>(rng.next() % n), j = static_cast<uint32_t>(rng.next() % n);
    for (int a = 0; a < 3; ++a) std::swap(st.position[a][i], st.position[a][j]);
    step("teleported");
  }
  // The list was reused on most steps and rebuilt on some.
  EXPECT_GT(builds, 2u);
  EXPECT_LT(builds, steps / 2);
}

}  // namespace sph_grid_test

namespace {

using sph_grid_test::run_moves;

TEST(SphCandidates, GiveTheFullSearchsPairsWhileTheTissueMoves) { run_moves(nullptr); }

TEST(SphCandidates, GiveTheFullSearchsPairsOverTheWorkers) {
  const sinew::test::ThreadPerRangeWorkers pool(3);
  run_moves(pool.workers());
}

}  // namespace
