// Golden determinism of the bar-net layer on the built-in rigs: the built
// model (offline doubles quantised) and every step's node and wrapped skin
// positions over a fixed trajectory hash to the committed values on every
// build (gcc, clang, aarch64, armhf). Besides the arm's elbow net: its q from
// an input (D re-factorised every step), its loads from a force input, the
// paper's Figure 3 and Figure 6 nets on the arm, and the nets any rig can
// carry (muscles, wrinkles) on the built-in hand; none allocates after init.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "golden.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/barnet/arm_session.hpp"
#include "host_tools/layers/barnet/muscle_net.hpp"
#include "host_tools/layers/barnet/wrinkle_net.hpp"
#include "sim_core/fixed/trig.hpp"
#include "tests/support/alloc_guard.hpp"

namespace det = sinew::determinism;
namespace bn = sinew::barnet;
using sinew::layers::barnet::ArmSession;
namespace lb = sinew::layers::barnet;

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

// External input k at step s (Q16.16): a triangle wave between lo and hi.
int32_t external_trajectory(uint32_t k, uint32_t step, double lo, double hi) {
  const uint32_t period = 90 + 13 * k, phase = (step * 5 + 7 * k) % period;
  const double tri = phase < period / 2 ? phase : period - phase;
  return static_cast<int32_t>((lo + (hi - lo) * tri / (period / 2)) * 65536.0);
}

struct Run {
  uint64_t model = 0, outputs = 0, allocations = 0;
  uint32_t saturated = 0;
};

// Steps the session over the trajectory (its external inputs, if any,
// between lo and hi) and hashes every step's nodes and wrapped skin; counts
// the heap allocations of the steps.
Run run(ArmSession& s, double lo = 0, double hi = 0) {
  Run r;
  r.model = model_hash(s.model());
  const int elbow = s.input("elbow.0");
  det::OutputHash out;
  sinew::test::AllocationCounter allocations;
  for (uint32_t step = 0; step < kSteps; ++step) {
    for (uint32_t i = 0; i < s.inputs().size(); ++i)
      s.inputs()[i] = trajectory(i, step, static_cast<int>(i) == elbow || elbow < 0);
    for (uint32_t k = 0; k < s.external().size(); ++k) s.external()[k] = external_trajectory(k, step, lo, hi);
    if (!s.step()) return r;
    for (size_t c = 0; c < 3; ++c) {
      for (int32_t v : s.outputs().node[c]) out.add_i32(v);
      for (int32_t v : s.outputs().skin[c]) out.add_i32(v);
    }
    out.add_u32(s.state().stats.saturated);
    r.saturated += s.state().stats.saturated;
  }
  r.allocations = allocations.allocations();
  r.outputs = out.digest();
  return r;
}

void expect_golden(const char* name, ArmSession& s, uint64_t golden, double lo = 0, double hi = 0) {
  ASSERT_TRUE(s.ok()) << name << ": " << s.error();
  const Run r = run(s, lo, hi);
  det::print_determinism_line((std::string("barnet-") + name).c_str(), r.outputs);
  EXPECT_EQ(r.allocations, 0u) << name << ": a step allocated";
  EXPECT_EQ(r.saturated, 0u) << name;
  EXPECT_EQ(r.outputs, golden) << name << ": bar-net outputs changed";
}

// A net of any rig at one of its joints, from the rig's geometry.
template <typename Options, typename Builder>
ArmSession::NetBuilder at_joint(const char* joint, Builder build, Options o = {}) {
  return [joint, build, o](const sinew::rigc::RigSpec& rig, lb::NetSpec* net, std::string* error) {
    sinew::layers::RigGeometry g;
    const int j = sinew::rigc::joint_index(rig, joint);
    return j >= 0 && sinew::layers::rig_geometry(rig, &g, error) && build(rig, g, j, o, net, error);
  };
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

TEST(BarnetDeterminism, ForceDensityFromAnInputMatchesGolden) {
  // Every bar's q scaled by external input 0 (1/4 .. 2) every step: D is
  // re-assembled and re-factorised each time.
  lb::ArmNetOptions o;
  o.q_input = true;
  ArmSession s(sinew::rigc::SkinChoice::kLinear, o);
  expect_golden("arm-q-input", s, sinew::test::barnet::golden::kArmQInput, 0.25, 2.0);
}

TEST(BarnetDeterminism, ForceInputMatchesGolden) {
  // The elbow net's loads activated by external input 0 (0 .. 40 N, full at
  // 40 N) instead of the flexion.
  ArmSession s(sinew::rigc::SkinChoice::kLinear,
               [](const sinew::rigc::RigSpec& arm, lb::NetSpec* net, std::string* error) {
                 if (!lb::arm_elbow_net(arm, {}, net, error)) return false;
                 lb::drive_from_inputs({1, 0, 0, 40, -1}, net);
                 return true;
               });
  expect_golden("arm-force-input", s, sinew::test::barnet::golden::kArmForceInput, -5.0, 45.0);
}

TEST(BarnetDeterminism, PapersFigureNetsOnTheArmMatchGolden) {
  ArmSession muscles(sinew::rigc::SkinChoice::kLinear,
                     [](const sinew::rigc::RigSpec& arm, lb::NetSpec* net, std::string* error) {
                       return lb::arm_muscle_net(arm, {}, net, error);
                     });
  expect_golden("arm-figure3", muscles, sinew::test::barnet::golden::kArmFigure3);
  ArmSession wrinkles(sinew::rigc::SkinChoice::kLinear,
                      [](const sinew::rigc::RigSpec& arm, lb::NetSpec* net, std::string* error) {
                        return lb::arm_wrinkle_net(arm, {}, net, error);
                      });
  expect_golden("arm-figure6", wrinkles, sinew::test::barnet::golden::kArmFigure6);
}

TEST(BarnetDeterminism, AnyRigNetsOnTheHandMatchGolden) {
  // The muscle net along the middle finger's proximal phalanx and the
  // wrinkle net at the index knuckle, built from the hand's geometry.
  ArmSession muscles(sinew::rigc::builtin_hand(sinew::rigc::SkinChoice::kLinear),
                     at_joint<lb::JointMuscleNetOptions>("middle_pip", lb::joint_muscle_net));
  expect_golden("hand-muscles", muscles, sinew::test::barnet::golden::kHandMuscles);
  ArmSession wrinkles(sinew::rigc::builtin_hand(sinew::rigc::SkinChoice::kLinear),
                      at_joint<lb::SkinWrinkleOptions>("index_mcp", lb::skin_wrinkle_net));
  expect_golden("hand-wrinkles", wrinkles, sinew::test::barnet::golden::kHandWrinkles);
}
