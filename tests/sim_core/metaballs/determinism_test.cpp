// Golden determinism of the metaballs layer: the model built offline from the
// built-in arm (doubles, -ffp-contract=off) and 300 steps of the engine plus
// the metaballs step over an integer trajectory must hash to the committed
// values on every build (gcc, clang, aarch64, armhf). Two workloads: per-step
// jiggle with smoothing, and jiggle in physical units at a converted rate
// with an action line.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/metaballs/step.hpp"
#include "tests/sim_core/metaballs/golden.hpp"

namespace {

namespace det = sinew::determinism;
namespace mb = sinew::metaballs;
namespace mbb = sinew::metaballs_build;
namespace fx = sinew::fx;

constexpr int kSteps = 300;

template <typename T>
void hash_bytes(det::OutputHash& h, const std::vector<T>& v) {
  // Records are hashed field by field as 32-bit words (their sizes are
  // multiples of 4).
  static_assert(sizeof(T) % 2 == 0);
  h.add_u32(static_cast<uint32_t>(v.size()));
  std::vector<uint8_t> bytes(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
  for (size_t i = 0; i + 1 < bytes.size(); i += 2)
    h.add_u32(static_cast<uint32_t>(bytes[i]) | (static_cast<uint32_t>(bytes[i + 1]) << 8));
}

// The model's arrays; `newer` adds the parts the first workload predates
// (action lines, the physical jiggle's rate), so its golden still names the
// same model.
uint64_t hash_model(const mbb::Build& b, bool newer) {
  det::OutputHash h;
  h.add_i32(b.length_exponent);
  hash_bytes(h, b.inverse_bind);
  hash_bytes(h, b.ball_rest);
  hash_bytes(h, b.ball_radius);
  hash_bytes(h, b.ball_bone);
  hash_bytes(h, b.ball_joint);
  hash_bytes(h, b.ball_weight);
  hash_bytes(h, b.ball_jiggle);
  hash_bytes(h, b.pairs);
  hash_bytes(h, b.bulges);
  hash_bytes(h, b.vertex_ball);
  hash_bytes(h, b.vertex_weight);
  hash_bytes(h, b.vertex_disp);
  hash_bytes(h, b.joint_balls);
  hash_bytes(h, b.jv_vertex);
  hash_bytes(h, b.jv_ball);
  hash_bytes(h, b.jv_alpha);
  hash_bytes(h, b.jv_blend);
  hash_bytes(h, b.jv_disp);
  hash_bytes(h, b.jv_laplacian);
  hash_bytes(h, b.jv_neighbour_begin);
  hash_bytes(h, b.jv_neighbours);
  hash_bytes(h, b.jv_inv_count);
  hash_bytes(h, b.overlaps);
  hash_bytes(h, b.overlap_vertices);
  hash_bytes(h, b.overlap_balls);
  h.add_u32(b.pbd_iterations);
  h.add_i32(b.jiggle_damping);
  h.add_u32(b.smoothing_passes);
  h.add_i32(b.smoothing_rate);
  if (newer) {
    hash_bytes(h, b.action_lines);
    hash_bytes(h, b.action_balls);
    h.add_u32(b.jiggle_rate_hz);
  }
  return h.digest();
}

// Integer triangle waves, +-90 degrees, a different period per input.
int32_t trajectory(uint32_t input, uint32_t step) {
  const uint32_t period = 512, phase = (step * (7 + 3 * input)) % period;
  const int32_t tri = static_cast<int32_t>(phase < period / 2 ? phase : period - phase);  // 0..256
  return (tri - 128) * (1 << 23);
}

struct Hashes {
  uint64_t model = 0, output = 0;
  uint32_t projected = 0;
};

// Builds the model, then runs kSteps of the engine plus the metaballs step
// (at tick_hz when > 0: physical jiggle gains converted at run time) and
// hashes every output vertex and ball centre.
Hashes run_workload(const mbb::Options& o, bool newer, uint32_t tick_hz) {
  Hashes out;
  const sinew::rigc::RigSpec spec = sinew::rigc::builtin_arm();
  mbb::Build build;
  std::string error;
  EXPECT_TRUE(mbb::build(spec, o, &build, &error)) << error;
  out.model = hash_model(build, newer);

  std::vector<uint8_t> bytes;
  sinew::rigc::CompileReport report;
  EXPECT_TRUE(sinew::rigc::compile_rig(spec, &bytes, &report, &error)) << error;
  std::vector<uint64_t> blob(bytes.size() / 8 + 1), rig_arena, engine_arena, state_memory;
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(blob.data());
  size_t rig_bytes = 0;
  EXPECT_TRUE(sinew::rig::rig_validate(data, bytes.size(), &rig_bytes).ok());
  rig_arena.resize(rig_bytes / 8 + 1);
  sinew::rig::Rig rig;
  EXPECT_TRUE(sinew::rig::rig_init(data, bytes.size(), rig_arena.data(), rig_arena.size() * 8, &rig).ok());
  engine_arena.resize(sinew::engine::engine_arena_bytes(rig) / 8 + 1);
  sinew::engine::Engine engine;
  EXPECT_TRUE(sinew::engine::engine_init(rig, engine_arena.data(), engine_arena.size() * 8, &engine));

  const mb::MetaballModel model = build.model();
  state_memory.resize(mb::metaballs_state_bytes(model) / 8 + 1);
  mb::MetaballState state;
  const mb::LayerStatus init = mb::metaballs_init(model, state_memory.data(), state_memory.size() * 8, &state);
  EXPECT_TRUE(init.ok()) << init.message;
  if (!init.ok()) return out;
  if (tick_hz > 0) {
    EXPECT_TRUE(mb::set_tick_rate(&state, tick_hz).ok());
  }
  std::vector<fx::Len> positions[3];
  sinew::skin::SkinnedVertices vertices;
  for (int a = 0; a < 3; ++a) {
    positions[a].assign(rig.vertex_count(), 0);
    vertices.position[a] = positions[a];
  }
  std::vector<int32_t> inputs(rig.input_count);
  det::OutputHash h;
  for (uint32_t s = 0; s < kSteps; ++s) {
    for (uint32_t i = 0; i < inputs.size(); ++i) inputs[i] = trajectory(i, s);
    EXPECT_TRUE(sinew::engine::engine_step(&engine, inputs));
    const mb::LayerStatus st = mb::metaballs_step(&state, engine.model, vertices);
    EXPECT_TRUE(st.ok()) << st.message;
    if (!st.ok()) return out;
    out.projected += state.stats.projected_vertices;
    for (int a = 0; a < 3; ++a)
      for (const fx::Len v : positions[a]) h.add_i32(v);
    for (const fx::Vec3& c : state.ball_center) {
      h.add_i32(c.x);
      h.add_i32(c.y);
      h.add_i32(c.z);
    }
  }
  out.output = h.digest();
  return out;
}

}  // namespace

// Per-step jiggle, bulging and the Laplacian smoothing on (the model of the
// first golden: options fixed so its hash still names it).
TEST(MetaballsDeterminism, ArmMatchesGolden) {
  mbb::Options o;
  o.ball_spacing = 0.01;
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
  o.jiggle.push_back({"forearm_twist", 0.2, 0.8, 0.2});
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  o.jiggle_frequency = 0;  // per-step gains
  o.smoothing_passes = 2;
  const Hashes h = run_workload(o, false, 0);
  det::print_determinism_line("metaballs-model", h.model);
  det::print_determinism_line("metaballs-arm", h.output);
  std::printf("metaballs determinism: %d steps, %u overlap projections in all\n", kSteps, h.projected);
  EXPECT_GT(h.projected, 0u) << "the trajectory should exercise the overlap stage";
  EXPECT_EQ(h.model, sinew::test::golden::kMetaballsModel) << "the built metaballs model changed";
  EXPECT_EQ(h.output, sinew::test::golden::kMetaballsArm) << "metaballs outputs changed";
}

// The newer behaviours: jiggle in physical units (the default gains, built
// for 1 kHz and converted to 500 Hz at run time), an action line, bulging.
TEST(MetaballsDeterminism, PhysicalJiggleAndActionLineMatchGolden) {
  mbb::Options o;
  o.ball_spacing = 0.01;
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
  o.jiggle.push_back({"forearm_twist", 0.2, 0.8, 0.2});
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  mbb::ActionLineSpec line;
  line.origin = "shoulder";
  line.insertion = "elbow";
  line.side[1] = 0.03;
  line.reach = 0.04;
  o.action_lines.push_back(line);
  const Hashes h = run_workload(o, true, 500);
  det::print_determinism_line("metaballs-physical-model", h.model);
  det::print_determinism_line("metaballs-physical-arm", h.output);
  EXPECT_GT(h.projected, 0u) << "the trajectory should exercise the overlap stage";
  EXPECT_EQ(h.model, sinew::test::golden::kMetaballsPhysicalModel) << "the built metaballs model changed";
  EXPECT_EQ(h.output, sinew::test::golden::kMetaballsPhysicalArm) << "metaballs outputs changed";
}
