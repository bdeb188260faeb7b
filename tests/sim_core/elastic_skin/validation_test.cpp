// Bad specs and bad inputs are rejected with a message naming the problem,
// never a crash.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "sim_core/elastic_skin/skin_validate.hpp"
#include "sim_core/muscle/muscle_validate.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;
namespace ab = sinew::anatomy_build;
namespace es = sinew::elastic_skin;
namespace muscle = sinew::muscle;

namespace {

void expect_message(const muscle::LayerStatus& st, const char* fragment) {
  std::printf("rejected: %s\n", st.message);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(std::string(st.message).find(fragment), std::string::npos) << st.message;
}

}  // namespace

// Every test checks against the built-in arm with its default anatomy.
class AnatomyValidation : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(arm.ok()) << arm.error(); }
  ArmAnatomy arm;
};

TEST_F(AnatomyValidation, MuscleWithOriginAfterInsertionInTheHierarchy) {
  // Builder: the spec swaps origin and insertion bones of the biceps.
  ArmAnatomy swapped([](ab::AnatomySpec& s) {
    std::swap(s.muscles[0].origin[0], s.muscles[0].insertion[0]);
    std::swap(s.muscles[0].origin[1], s.muscles[0].insertion[1]);
  });
  std::printf("builder: %s\n", swapped.error().c_str());
  EXPECT_FALSE(swapped.ok());
  EXPECT_NE(swapped.error().find("origin is after the insertion"), std::string::npos);
  EXPECT_NE(swapped.error().find("muscle[0]"), std::string::npos);

  // Runtime validator on an otherwise good model.
  std::vector<muscle::MuscleRecord> bad(arm.model().muscles);
  std::swap(bad[1].origin[0].bone, bad[1].insertion[0].bone);
  muscle::MuscleModel m = arm.muscle_model();
  m.muscles = bad;
  expect_message(muscle::muscle_validate(m, arm.rig()), "muscle[1].origin.bone: origin is after the insertion");
}

TEST_F(AnatomyValidation, AnchorOutsideEveryComponent) {
  // Builder: components' reach shrunk below the skin's distance to them.
  ArmAnatomy far([](ab::AnatomySpec& s) { s.skin.max_anchor_distance = 0.005; });
  std::printf("builder: %s\n", far.error().c_str());
  EXPECT_FALSE(far.ok());
  EXPECT_NE(far.error().find("anchor outside every component"), std::string::npos);

  // Runtime validator: a muscle anchor whose u lies far outside its cell,
  // and a bone anchor naming no joint.
  std::vector<es::Anchor> anchors(arm.model().anchors);
  uint32_t v = 0;
  while (anchors[v].kind != static_cast<uint8_t>(es::AnchorKind::kMuscle)) ++v;
  anchors[v].param[2] = 5 << 24;
  es::SkinModel skin = arm.skin_model();
  skin.anchors = anchors;
  expect_message(es::skin_validate(skin, arm.rig(), arm.muscle_model()), "anchor outside every component");
  anchors[v] = arm.model().anchors[v];
  anchors[0].kind = static_cast<uint8_t>(es::AnchorKind::kBone);
  anchors[0].component = 99;
  expect_message(es::skin_validate(skin, arm.rig(), arm.muscle_model()), "skin anchor[0].component");
  // The step re-checks and refuses too (no out-of-bounds read).
  ASSERT_TRUE(arm.step().ok());
  expect_message(es::skin_step(skin, arm.muscle_model(), arm.muscles(), arm.engine().model, &arm.skin()),
                 "skin anchor[0].component");
}

TEST_F(AnatomyValidation, BadMuscleAndPrimitiveRecords) {
  const auto check = [&](auto edit, const char* fragment) {
    std::vector<muscle::MuscleRecord> ms(arm.model().muscles);
    std::vector<muscle::PrimitiveRecord> ps(arm.model().primitives);
    muscle::MuscleModel m = arm.muscle_model();
    edit(m, ms, ps);
    m.muscles = ms;
    m.primitives = ps;
    expect_message(muscle::muscle_validate(m, arm.rig()), fragment);
  };
  using MM = muscle::MuscleModel;
  using MV = std::vector<muscle::MuscleRecord>;
  using PV = std::vector<muscle::PrimitiveRecord>;
  check([](MM& m, MV&, PV&) { m.ring_vertices = 6; }, "ring_vertices");
  check([](MM&, MV& ms, PV&) { ms[0].insertion[1].bone = 40; }, "muscle[0].insertion.bone");
  check([](MM&, MV& ms, PV&) { ms[0].pivot_slice = 7; }, "muscle[0].pivot_slice");
  check([](MM&, MV& ms, PV&) { ms[1].rest_length = 0; }, "muscle[1].rest_length");
  check([](MM&, MV& ms, PV&) { ms[1].half_width[3] = -1; }, "negative slice radius");
  check([](MM&, MV&, PV& ps) { ps[0].exponent = 3; }, "primitive[0].exponent");
  check([](MM&, MV&, PV& ps) { ps[1].extent[2] = 0; }, "primitive[1].extent: must be > 0");
  check([](MM&, MV&, PV& ps) { ps[1].extent[2] = ps[1].extent[0] * 100; }, "aspect ratio");
  check([](MM&, MV&, PV& ps) { ps[0].segment = 7; }, "primitive[0].segment");
  check([](MM&, MV&, PV& ps) { ps[0].kind = 9; }, "primitive[0].kind");
  check(
      [](MM&, MV&, PV& ps) {
        ps[0].kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSphere);
        ps[0].exponent = 2;
      },
      "a sphere needs three equal extents");
}

TEST_F(AnatomyValidation, BadPrimitiveDeformations) {
  // Barr's deformations outside their documented ranges (muscle_model.hpp).
  const size_t n = arm.model().primitives.size();
  ASSERT_GT(n, 0u);
  const auto validate = [&](auto edit) {
    std::vector<muscle::PrimitiveDeformation> ds(n);
    edit(ds);
    muscle::MuscleModel m = arm.muscle_model();
    m.deformations = ds;
    return muscle::muscle_validate(m, arm.rig());
  };
  using DV = std::vector<muscle::PrimitiveDeformation>;
  constexpr int32_t kDegree = 11930465;  // 2^32 / 360
  // In range: accepted (a mild bend keeps its centre clear of the shape).
  EXPECT_TRUE(validate([](DV& d) {
                d[0].taper = muscle::kMaxTaper;
                d[0].twist = -muscle::kMaxTwist;
                d[0].bend = 5 * kDegree;
              }).ok());
  expect_message(validate([](DV& d) { d[0].taper = muscle::kMaxTaper + 1; }), "primitive[0].deformation.taper");
  expect_message(validate([](DV& d) { d[0].twist = muscle::kMaxTwist + 1; }), "primitive[0].deformation.twist");
  expect_message(validate([](DV& d) { d[0].bend = muscle::kMinBend - 1; }), "primitive[0].deformation.bend");
  expect_message(validate([](DV& d) { d[0].bend = -(muscle::kMaxBend + 1); }), "primitive[0].deformation.bend");
  expect_message(validate([](DV& d) { d[0].bend = muscle::kMaxBend; }), "bend radius below");
  expect_message(validate([](DV& d) { d.pop_back(); }), "deformations");
  // The superellipsoid exponent: 2, 4 or 8 only (documented range).
  for (const int exponent : {1, 6, 16}) {
    std::vector<muscle::PrimitiveRecord> ps(arm.model().primitives);
    ps[0].kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid);
    ps[0].exponent = static_cast<uint8_t>(exponent);
    muscle::MuscleModel m = arm.muscle_model();
    m.primitives = ps;
    expect_message(muscle::muscle_validate(m, arm.rig()), "primitive[0].exponent");
  }
}

TEST_F(AnatomyValidation, BadSkinParametersAndRecords) {
  const auto check = [&](auto edit, const char* fragment) {
    std::vector<es::Edge> edges(arm.model().edges);
    std::vector<sinew::fx::Len> fat(arm.model().fat);
    es::SkinModel s = arm.skin_model();
    edit(s, edges, fat);
    s.edges = edges;
    s.fat = fat;
    expect_message(es::skin_validate(s, arm.rig(), arm.muscle_model()), fragment);
  };
  using SM = es::SkinModel;
  using EV = std::vector<es::Edge>;
  using FV = std::vector<sinew::fx::Len>;
  check([](SM& s, EV&, FV&) { s.params.iterations = 0; }, "iterations");
  check([](SM& s, EV&, FV&) { s.params.iterations = 1000; }, "iterations");
  check([](SM& s, EV&, FV&) { s.params.push_back = -1; }, "push_back");
  check([](SM& s, EV&, FV&) { s.params.compression_band = 0; }, "compression_band");
  check([](SM& s, EV&, FV&) { s.params.reaction_gain = 0; }, "reaction_gain");
  check([](SM& s, EV&, FV&) { s.params.newton_steps = 9; }, "newton_steps");
  check([](SM& s, EV&, FV&) { s.params.collision_radius = -5; }, "collision_radius");
  check([](SM&, EV& e, FV&) { e[3].b = e[3].a; }, "skin edge[3].a/b");
  check([](SM&, EV& e, FV&) { e[4].k = es::kMaxStiffness + 1; }, "skin edge[4].k");
  check([](SM&, EV& e, FV&) { e[5].rest = -1; }, "skin edge[5].rest");
  check([](SM&, EV&, FV& f) { f[7] = -1; }, "skin fat[7]");
  check([](SM& s, EV&, FV&) { s.vertex_count += 1; }, "sizes differ from vertex_count");
}

TEST_F(AnatomyValidation, BadStepInputsAndMemory) {
  ASSERT_TRUE(arm.step().ok());
  const std::span<const sinew::fx::Mat34> short_bones = arm.engine().model.first(2);
  expect_message(muscle::muscle_step(arm.muscle_model(), short_bones, &arm.muscles()), "bones");
  expect_message(es::skin_step(arm.skin_model(), arm.muscle_model(), arm.muscles(), short_bones, &arm.skin()), "bones");
  // State memory: too small, misaligned, or missing.
  std::vector<uint64_t> small(4);
  muscle::MuscleState ms;
  expect_message(muscle::muscle_init(arm.muscle_model(), small.data(), 32, &ms), "smaller than");
  expect_message(muscle::muscle_init(arm.muscle_model(), reinterpret_cast<uint8_t*>(small.data()) + 1, 31, &ms),
                 "aligned");
  es::SkinState ss;
  expect_message(es::skin_init(arm.skin_model(), nullptr, 0, &ss), "aligned");
  expect_message(es::skin_init(arm.skin_model(), small.data(), 32, &ss), "smaller than");
  // A skin state built for another model.
  es::SkinModel other = arm.skin_model();
  other.vertex_count = 3;
  expect_message(es::skin_step(other, arm.muscle_model(), arm.muscles(), arm.engine().model, &arm.skin()),
                 "not initialised for this skin model");
}
