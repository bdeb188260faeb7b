// Golden determinism of the metaballs layer: the model built offline from the
// built-in arm (doubles, -ffp-contract=off) and 300 steps of the engine plus
// the metaballs step over an integer trajectory must hash to the committed
// values on every build (gcc, clang, aarch64, armhf).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/metaballs/step.hpp"
#include "tests/metaballs/golden.hpp"

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

uint64_t hash_model(const mbb::Build& b) {
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
  return h.digest();
}

// Integer triangle waves, +-90 degrees, a different period per input.
int32_t trajectory(uint32_t input, uint32_t step) {
  const uint32_t period = 512, phase = (step * (7 + 3 * input)) % period;
  const int32_t tri = static_cast<int32_t>(phase < period / 2 ? phase : period - phase);  // 0..256
  return (tri - 128) * (1 << 23);
}

}  // namespace

TEST(MetaballsDeterminism, ArmMatchesGolden) {
  mbb::Options o;
  o.ball_spacing = 0.01;
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
  o.jiggle.push_back({"forearm_twist", 0.2, 0.8, 0.2});
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  const sinew::rigc::RigSpec spec = sinew::rigc::builtin_arm();
  mbb::Build build;
  std::string error;
  ASSERT_TRUE(mbb::build(spec, o, &build, &error)) << error;
  const uint64_t model_hash = hash_model(build);
  det::print_determinism_line("metaballs-model", model_hash);

  std::vector<uint8_t> bytes;
  sinew::rigc::CompileReport report;
  ASSERT_TRUE(sinew::rigc::compile_rig(spec, &bytes, &report, &error)) << error;
  std::vector<uint64_t> blob(bytes.size() / 8 + 1), rig_arena, engine_arena, state_memory;
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(blob.data());
  size_t rig_bytes = 0;
  ASSERT_TRUE(sinew::rig::rig_validate(data, bytes.size(), &rig_bytes).ok());
  rig_arena.resize(rig_bytes / 8 + 1);
  sinew::rig::Rig rig;
  ASSERT_TRUE(sinew::rig::rig_init(data, bytes.size(), rig_arena.data(), rig_arena.size() * 8, &rig).ok());
  engine_arena.resize(sinew::engine::engine_arena_bytes(rig) / 8 + 1);
  sinew::engine::Engine engine;
  ASSERT_TRUE(sinew::engine::engine_init(rig, engine_arena.data(), engine_arena.size() * 8, &engine));

  const mb::MetaballModel model = build.model();
  state_memory.resize(mb::state_bytes(model) / 8 + 1);
  mb::MetaballState state;
  const mb::Status init = mb::init(model, state_memory.data(), state_memory.size() * 8, &state);
  ASSERT_TRUE(init.ok()) << init.message;
  std::vector<fx::Len> out[3];
  sinew::skin::SkinnedVertices vertices;
  for (int a = 0; a < 3; ++a) {
    out[a].assign(rig.vertex_count(), 0);
    vertices.position[a] = out[a];
  }
  std::vector<int32_t> inputs(rig.input_count);
  det::OutputHash h;
  uint32_t projected = 0;
  for (uint32_t s = 0; s < kSteps; ++s) {
    for (uint32_t i = 0; i < inputs.size(); ++i) inputs[i] = trajectory(i, s);
    ASSERT_TRUE(sinew::engine::engine_step(&engine, inputs));
    const mb::Status st = mb::step(&state, engine.model, vertices);
    ASSERT_TRUE(st.ok()) << st.message;
    projected += state.stats.projected_vertices;
    for (int a = 0; a < 3; ++a)
      for (const fx::Len v : out[a]) h.add_i32(v);
    for (const fx::Vec3& c : state.ball_center) {
      h.add_i32(c.x);
      h.add_i32(c.y);
      h.add_i32(c.z);
    }
  }
  const uint64_t output_hash = h.digest();
  det::print_determinism_line("metaballs-arm", output_hash);
  std::printf("metaballs determinism: %d steps, %u overlap projections in all\n", kSteps, projected);
  EXPECT_GT(projected, 0u) << "the trajectory should exercise the overlap stage";
  EXPECT_EQ(model_hash, sinew::test::golden::kMetaballsModel) << "the built metaballs model changed";
  EXPECT_EQ(output_hash, sinew::test::golden::kMetaballsArm) << "metaballs outputs changed";
}
