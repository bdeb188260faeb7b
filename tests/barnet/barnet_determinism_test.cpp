// Golden determinism of the bar-net layer on the built-in arm: the built
// model (offline doubles quantised) and every step's node and wrapped skin
// positions over a fixed trajectory hash to the committed values on every
// build (gcc, clang, aarch64, armhf).
#include <gtest/gtest.h>

#include "golden.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/barnet/arm_session.hpp"
#include "sim_core/fixed/trig.hpp"

namespace det = sinew::determinism;
namespace bn = sinew::barnet;
using sinew::layers::barnet::ArmSession;

namespace {

constexpr int kSteps = 300;

void add(det::OutputHash& h, sinew::fx::Vec3 v) {
  h.add_i32(v.x);
  h.add_i32(v.y);
  h.add_i32(v.z);
}

uint64_t model_hash(const bn::BarnetModel& m) {
  det::OutputHash h;
  h.add_u32(m.joint_count);
  h.add_u32(m.input_count);
  h.add_u32(m.vertex_count);
  for (const sinew::fx::Mat34& b : m.inverse_bind) {
    for (const auto& row : b.m)
      for (int32_t v : row) h.add_i32(v);
    for (int32_t v : b.t) h.add_i32(v);
  }
  for (const bn::NodeRecord& n : m.nodes) {
    add(h, n.rest);
    h.add_u32(n.kind);
    h.add_u32(n.influence_count);
    for (uint32_t k = 0; k < bn::kMaxNodeInfluences; ++k) {
      h.add_u32(n.joint[k]);
      h.add_i32(n.weight[k]);
    }
  }
  for (const bn::BarRecord& b : m.bars) {
    h.add_u32(b.a);
    h.add_u32(b.b);
    h.add_i32(b.q);
  }
  for (const bn::LoadRecord& l : m.loads) {
    h.add_u32(l.node);
    h.add_u32(l.joint);
    h.add_u32(l.input);
    h.add_i32(l.angle_lo);
    h.add_i32(l.angle_hi);
    add(h, l.force);
  }
  for (const bn::ControlTriangle& t : m.triangles)
    for (uint32_t v : t.node) h.add_u32(v);
  for (const bn::WrapRecord& w : m.wrap) {
    h.add_u32(w.vertex);
    h.add_u32(w.triangle);
    for (int32_t b : w.bary) h.add_i32(b);
    h.add_i32(w.offset);
  }
  return h.digest();
}

// Input i at step s: a triangle wave between lo and hi degrees (integer
// binary angles), each input with its own phase and period.
int32_t trajectory(uint32_t input, uint32_t step, bool elbow) {
  const int64_t lo = elbow ? -10 : -60, hi = elbow ? 160 : 60;
  const uint32_t period = 120 + 17 * input, phase = (step * 3 + 29 * input) % period;
  const int64_t tri = phase < period / 2 ? phase : period - phase;  // 0 .. period/2
  const int64_t deg_q16 = (lo * 65536) + (hi - lo) * 65536 * tri / (period / 2);
  return static_cast<int32_t>(sinew::fx::angle_from_deg_q16(static_cast<int32_t>(deg_q16)));
}

}  // namespace

TEST(BarnetDeterminism, ArmMatchesGolden) {
  ArmSession s;
  ASSERT_TRUE(s.ok()) << s.error();
  const uint64_t model = model_hash(s.model());
  const size_t elbow = static_cast<size_t>(s.input("elbow.0"));
  det::OutputHash out;
  for (uint32_t step = 0; step < kSteps; ++step) {
    for (uint32_t i = 0; i < s.inputs().size(); ++i) s.inputs()[i] = trajectory(i, step, i == elbow);
    ASSERT_TRUE(s.step());
    for (size_t c = 0; c < 3; ++c) {
      for (int32_t v : s.outputs().node[c]) out.add_i32(v);
      for (int32_t v : s.outputs().skin[c]) out.add_i32(v);
    }
    out.add_u32(s.state().stats.saturated);
  }
  const uint64_t outputs = out.digest();
  det::print_determinism_line("barnet-arm-model", model);
  det::print_determinism_line("barnet-arm", outputs);
  EXPECT_EQ(model, sinew::test::barnet::golden::kArmModel) << "the built arm bar-net changed";
  EXPECT_EQ(outputs, sinew::test::barnet::golden::kArmOutputs) << "bar-net outputs on the arm changed";
}
