// Bad parameters are rejected with a message naming the field, by the
// builder and by the run-time validator; bad step inputs change nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "sph_fixture.hpp"

namespace layers = sinew::layers;
namespace sph = sinew::sph;

namespace {

std::string build_error(const layers::SphBuildOptions& o) {
  layers::SphBuilt b;
  std::string error;
  EXPECT_FALSE(layers::build_sph(sinew::rigc::builtin_arm(), o, &b, &error));
  std::printf("rejected: %s\n", error.c_str());
  return error;
}

layers::SphBuilt small_model() {
  layers::SphBuildOptions o;
  o.particle_count = 300;
  layers::SphBuilt b;
  std::string error;
  EXPECT_TRUE(layers::build_sph(sinew::rigc::builtin_arm(), o, &b, &error)) << error;
  return b;
}

std::string validate_error(const sph::SphModel& m) {
  const sph::LayerStatus s = sph::sph_validate_model(m);
  EXPECT_FALSE(s.ok());
  std::printf("rejected: %s\n", s.message);
  return s.message;
}

}  // namespace

TEST(SphValidation, BuilderRejectsBadOptions) {
  layers::SphBuildOptions o;
  o.particle_count = 0;
  EXPECT_NE(build_error(o).find("particle_count"), std::string::npos);
  o.particle_count = 9000;
  EXPECT_NE(build_error(o).find("8192"), std::string::npos);
  o = {};
  o.particle_count = 300;
  o.override_h = 0;
  EXPECT_NE(build_error(o).find("h "), std::string::npos);
  o = {};
  o.particle_count = 300;
  o.override_tau_f = 0;
  EXPECT_NE(build_error(o).find("tau_f"), std::string::npos);
  o = {};
  o.distal_joint = "knee";
  EXPECT_NE(build_error(o).find("knee"), std::string::npos);
}

TEST(SphValidation, ValidatorRejectsBadModels) {
  const layers::SphBuilt b = small_model();
  ASSERT_TRUE(sph::sph_validate_model(b.model()).ok());
  sph::SphModel m = b.model();
  m.params.h = 0;
  EXPECT_NE(validate_error(m).find("h "), std::string::npos);
  m = b.model();
  m.params.tau_f = 0;
  EXPECT_NE(validate_error(m).find("tau_f"), std::string::npos);
  m.params.tau_f = -5;
  EXPECT_NE(validate_error(m).find("tau_f"), std::string::npos);
  m = b.model();
  m.bone = {};
  EXPECT_NE(validate_error(m).find("particle count"), std::string::npos);
  m = b.model();
  m.params.substeps = 0;
  EXPECT_NE(validate_error(m).find("substeps"), std::string::npos);
  m = b.model();
  m.params.damping = 0;
  EXPECT_NE(validate_error(m).find("damping"), std::string::npos);
  // A joint the rig does not have: only the check against the rig sees it.
  m = b.model();
  m.joint.distal_joint = 7;
  EXPECT_TRUE(sph::sph_validate_model(m).ok());
  const sinew::test::SphArm arm(layers::SphBuildOptions{});
  ASSERT_TRUE(arm.ok()) << arm.error();
  const sph::LayerStatus against_rig = sph::sph_validate(m, arm.rig());
  EXPECT_FALSE(against_rig.ok());
  EXPECT_NE(std::string(against_rig.message).find("distal_joint"), std::string::npos) << against_rig.message;
  // A particle count beyond the documented maximum.
  std::vector<uint8_t> bones(sph::kMaxParticles + 1, 1);
  std::vector<sinew::fx::Len> zeros(bones.size(), 0);
  m = b.model();
  m.bone = bones;
  for (int a = 0; a < 3; ++a) m.rest_local[a] = m.rest_model[a] = zeros;
  EXPECT_NE(validate_error(m).find("8192"), std::string::npos);
}

TEST(SphValidation, StepRejectsBadInputsAndChangesNothing) {
  layers::SphBuildOptions o;
  o.particle_count = 300;
  sinew::test::SphArm arm(o);
  ASSERT_TRUE(arm.ok()) << arm.error();
  const int32_t before = arm.state().position[0][0];
  sph::SphInputs in;
  in.transforms = arm.engine().model.first(1);
  sph::LayerStatus s = sph::sph_step(&arm.state(), in);
  EXPECT_EQ(s.error, sph::LayerError::kBadInput);
  std::printf("rejected: %s\n", s.message);
  in.transforms = arm.engine().model;
  in.force = {INT32_MAX, 0, 0};
  s = sph::sph_step(&arm.state(), in);
  EXPECT_EQ(s.error, sph::LayerError::kBadInput);
  std::printf("rejected: %s\n", s.message);
  EXPECT_EQ(arm.state().position[0][0], before);
  EXPECT_EQ(arm.state().stats.steps, 0u);
  std::vector<uint64_t> tiny(4);
  sph::SphState st;
  s = sph::sph_init(arm.model(), arm.engine().model, tiny.data(), tiny.size() * 8, &st);
  EXPECT_EQ(s.error, sph::LayerError::kArena);
  std::printf("rejected: %s\n", s.message);
}

// §5 calibrates tau_f at "the maximum bendable angle": by default the
// builder flexes the tissue to the driven joint's upper limit, at most 90
// degrees (beyond it the elastic pull has no static equilibrium; docs/sph.md).
TEST(SphCalibration, DefaultIsTheJointsMaximumFlexionUpTo90Degrees) {
  const auto tau_f = [](const sinew::rigc::RigSpec& spec, double yield_angle_deg) {
    layers::SphBuildOptions o;
    o.particle_count = 300;
    o.yield_angle_deg = yield_angle_deg;
    layers::SphBuilt b;
    std::string error;
    EXPECT_TRUE(layers::build_sph(spec, o, &b, &error)) << error;
    return b.params.tau_f;
  };
  sinew::rigc::RigSpec arm = sinew::rigc::builtin_arm();
  const int elbow = sinew::rigc::joint_index(arm, "elbow");
  ASSERT_GE(elbow, 0);
  ASSERT_EQ(arm.joints[static_cast<size_t>(elbow)].dofs[0].max, 150);
  // The arm's elbow flexes to 150 degrees: capped at 90.
  EXPECT_EQ(layers::calibration_angle_deg(arm, elbow, 0), 90);
  EXPECT_EQ(tau_f(arm, 0), tau_f(arm, 90));
  // A joint that stops at 45 degrees yields at its own limit, and less
  // flexion compresses the crease less.
  sinew::rigc::RigSpec stiff = arm;
  stiff.joints[static_cast<size_t>(elbow)].dofs[0].max = 45;
  EXPECT_EQ(layers::calibration_angle_deg(stiff, elbow, 0), 45);
  EXPECT_EQ(tau_f(stiff, 0), tau_f(stiff, 45));
  EXPECT_LT(tau_f(stiff, 0), tau_f(arm, 0));
  // A rig's override wins.
  EXPECT_EQ(layers::calibration_angle_deg(arm, elbow, 60), 60);
  EXPECT_EQ(tau_f(arm, 60), tau_f(stiff, 60));
}
