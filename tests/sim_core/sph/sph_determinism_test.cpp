// Golden determinism of the SPH elastic elbow on the built-in arm: the
// offline model (built in double, -ffp-contract=off) and every tick's
// outputs (particles, pressures, yield flags, bend, joint yield, flexed
// distal frame, eq. (2) skin offsets and the skinned vertices they move)
// must hash to the committed value on every build (x86_64, aarch64, armhf).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "host_tools/determinism/output_hash.hpp"
#include "sph_fixture.hpp"
#include "tests/sim_core/sph/golden.hpp"
#include "tests/support/test_workers.hpp"

namespace det = sinew::determinism;
using sinew::test::SphArm;

namespace {

constexpr uint32_t kParticles = 500;
constexpr int kTicks = 300;

void add_model(det::OutputHash* h, const sinew::sph::SphModel& m) {
  const auto& p = m.params;
  for (int32_t v :
       {p.h, p.elastic_gain, p.pressure_gain, p.viscosity_gain, p.damping, p.load_gain, p.tau_f, p.grid_radius})
    h->add_i32(v);
  for (uint32_t v : {p.substeps, p.max_neighbours, p.yield_count, m.joint.proximal_joint, m.joint.distal_joint})
    h->add_u32(v);
  for (int32_t v : {m.joint.axis.x, m.joint.axis.y, m.joint.axis.z, m.joint.load_point.x, m.joint.load_point.y,
                    m.joint.load_point.z})
    h->add_i32(v);
  for (int c = 0; c < 3; ++c) {
    for (int32_t v : m.rest_local[c]) h->add_i32(v);
    for (int32_t v : m.rest_model[c]) h->add_i32(v);
    for (int32_t v : m.skin_rest[c]) h->add_i32(v);
  }
  for (uint8_t b : m.bone) h->add_u32(b);
  for (uint32_t v : m.skin_vertex) h->add_u32(v);
}

void add_tick(det::OutputHash* h, const sinew::sph::SphState& s, const sinew::engine::Engine& e) {
  const sinew::sph::SphModel& m = *s.model;
  for (int c = 0; c < 3; ++c)
    for (int32_t v : s.position[c]) h->add_i32(v);
  for (int32_t v : s.pressure) h->add_i32(v);
  for (uint8_t y : s.yielded) h->add_u32(y);
  h->add_u32(static_cast<uint32_t>(s.bend));
  h->add_u32(s.joint_yielded ? 1u : 0u);
  h->add_u32(s.yielded_particles);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) h->add_i32(s.distal_flexed.m[r][c]);
  for (int c = 0; c < 3; ++c) h->add_i32(s.distal_flexed.t[c]);
  for (int c = 0; c < 3; ++c) {
    for (int32_t v : s.skin_offset[c]) h->add_i32(v);
    for (uint32_t v : m.skin_vertex) h->add_i32(e.vertices.position[c][v]);
  }
}

struct SphWorkload {
  uint64_t digest = 0;
  double bend = 0;
  uint32_t yielded = 0;        // the most particles yielding at once
  bool joint_yielded = false;  // the joint yielded in some tick
  int gathered = 0;            // ticks whose last substep's pairs were searched over the workers and gathered
  uint32_t overflow = 0;       // neighbours dropped by max_neighbours over the run
};

// Integer-only workload: the elbow swings on a triangle wave (binary angle,
// +-2^28 = +-22.5 deg), a side force ramps to 30 N over 200 ticks (enough
// for the Tresca yield) and is released, with a small sawtooth along x.
// workers: null, or the threads the step may use (the same words for any).
SphWorkload run_sph_workload(const sinew::layers::SphBuildOptions& options, bool hash_tension,
                             const sinew::layer::Workers* workers = nullptr, int ticks = kTicks) {
  SphWorkload w;
  SphArm arm(options);
  EXPECT_TRUE(arm.ok()) << arm.error();
  const int elbow = arm.input("elbow.0");
  EXPECT_GE(elbow, 0);
  if (!arm.ok() || elbow < 0) return w;
  det::OutputHash h;
  add_model(&h, arm.model());
  if (hash_tension) h.add_i32(arm.model().params.tension_gain);
  for (int t = 0; t < ticks; ++t) {
    const int32_t phase = t % 200;
    arm.inputs()[static_cast<size_t>(elbow)] = (phase < 100 ? phase : 200 - phase) * (int32_t{1} << 22);
    const int64_t fy = t < 200 ? (int64_t{30} << 16) * (t + 1) / 200 : 0;
    const int32_t fx = ((t % 64) - 32) * (int32_t{1} << 14);
    EXPECT_TRUE(sinew::engine::engine_step(&arm.engine(), arm.inputs()));
    sinew::sph::SphInputs in;
    in.transforms = arm.engine().model;
    in.force = {fx, static_cast<int32_t>(fy), 0};
    in.tresca = true;
    in.workers = workers;
    const sinew::sph::LayerStatus st = sinew::sph::sph_step(&arm.state(), in);
    EXPECT_TRUE(st.ok()) << st.message;
    if (!st.ok()) return w;
    sinew::sph::sph_apply_skin(arm.state(), arm.engine().vertices.position);
    add_tick(&h, arm.state(), arm.engine());
    w.yielded = std::max(w.yielded, arm.state().yielded_particles);
    w.joint_yielded = w.joint_yielded || arm.state().joint_yielded;
    w.gathered += arm.state().gathered ? 1 : 0;
    w.overflow += arm.state().stats.neighbour_overflow;
  }
  w.digest = h.digest();
  w.bend = arm.bend_degrees();
  return w;
}

}  // namespace

TEST(SphDeterminism, ArmWorkloadMatchesGolden) {
  sinew::layers::SphBuildOptions options;
  options.particle_count = kParticles;
  const SphWorkload w = run_sph_workload(options, false);
  std::printf(
      "sph determinism: %u particles, %d ticks, final bend %.2f deg, most yielded particles %u, joint yielded %s\n",
      kParticles, kTicks, w.bend, w.yielded, w.joint_yielded ? "yes" : "no");
  det::print_determinism_line("sph-arm", w.digest);
  EXPECT_GT(w.yielded, 0u) << "the workload should exercise the Tresca yield";
  EXPECT_EQ(w.digest, sinew::test::golden::kSphArm) << "sph outputs on the arm changed";
}

// The same workload with the colour-field surface tension on (sigma = 1
// N/m; off on the built-in rigs, docs/sph.md): its own golden, so the
// tension path is held bit-identical across builds too.
TEST(SphDeterminism, ArmWorkloadWithSurfaceTensionMatchesGolden) {
  sinew::layers::SphBuildOptions options;
  options.particle_count = kParticles;
  options.surface_tension = 1.0;
  const SphWorkload w = run_sph_workload(options, true);
  std::printf("sph determinism with surface tension: final bend %.2f deg, yielded particles %u\n", w.bend, w.yielded);
  det::print_determinism_line("sph-arm-tension", w.digest);
  EXPECT_EQ(w.digest, sinew::test::golden::kSphArmSurfaceTension) << "sph outputs with surface tension changed";
}

// Workers change no output word: the search by ranges of particles, the
// gathered sides and the per-particle loops (sph_grid.hpp) give the words of
// the step on one thread for every worker count, with and without the
// tension's sums, and every tick must have taken that path (a step that
// ignored its workers would pass the hashes alone). The test pool runs a loop's ranges in reverse order, each on its
// own thread. Shorter than the golden run: thread starts are slow under
// qemu.
constexpr int kWorkerTicks = 80;

TEST(SphDeterminism, EveryWorkerCountGivesTheSameWords) {
  for (const bool tension : {false, true}) {
    sinew::layers::SphBuildOptions options;
    options.particle_count = kParticles;
    if (tension) options.surface_tension = 1.0;
    const SphWorkload serial = run_sph_workload(options, tension, nullptr, kWorkerTicks);
    for (const uint32_t parts : {2u, 3u, 4u, 7u}) {
      sinew::test::ThreadPerRangeWorkers pool(parts);
      const SphWorkload w = run_sph_workload(options, tension, pool.workers(), kWorkerTicks);
      EXPECT_EQ(w.digest, serial.digest) << parts << " workers" << (tension ? ", surface tension" : "");
      EXPECT_EQ(w.gathered, kWorkerTicks) << parts << " workers: the pairs were not searched over the workers";
      EXPECT_GT(pool.loops(), 0u) << parts << " workers: no loop ran over the workers";
    }
  }
}

// Lists that overflow max_neighbours take the ordered per-particle scan,
// which decides which neighbours drop: with workers too, the same words.
TEST(SphDeterminism, OverflowingListsAreTheSameOverWorkers) {
  sinew::layers::SphBuildOptions options;
  options.particle_count = kParticles;
  options.max_neighbours = 12;
  const SphWorkload serial = run_sph_workload(options, false, nullptr, kWorkerTicks);
  ASSERT_GT(serial.overflow, 0u) << "max_neighbours 12 should overflow some lists";
  for (const uint32_t parts : {2u, 4u}) {
    sinew::test::ThreadPerRangeWorkers pool(parts);
    const SphWorkload w = run_sph_workload(options, false, pool.workers(), kWorkerTicks);
    EXPECT_EQ(w.digest, serial.digest) << parts << " workers";
    EXPECT_EQ(w.overflow, serial.overflow) << parts << " workers";
  }
}
