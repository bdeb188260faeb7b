// A recording's description of its run: encoded and parsed back exactly;
// anything missing, unknown or malformed refused with the line named.
#include "firmware/runtime/recording.hpp"

#include <gtest/gtest.h>

namespace fw = sinew::firmware;

TEST(RunDescription, RoundTripsEveryField) {
  fw::RunDescription run;
  run.rig_xxh64 = 0x0123456789abcdefull;
  run.rig_bytes = 123456;
  run.options.tick_hz = 1000;
  using sinew::pipeline::Stage;
  run.options.stages = sinew::pipeline::StageSet::none();
  run.options.stages.set(Stage::kMetaballs, true);
  run.options.stages.set(Stage::kAnatomy, true);
  run.options.sph.tresca = false;
  run.options.anatomy.skin_iterations = 7;
  fw::RunDescription back;
  std::string error;
  ASSERT_TRUE(fw::parse_run_description(fw::encode_run_description(run), &back, &error)) << error;
  EXPECT_EQ(back.rig_xxh64, run.rig_xxh64);
  EXPECT_EQ(back.rig_bytes, run.rig_bytes);
  EXPECT_EQ(back.options.tick_hz, 1000u);
  EXPECT_FALSE(back.options.stages.has(Stage::kSph));
  EXPECT_TRUE(back.options.stages.has(Stage::kMetaballs));
  EXPECT_FALSE(back.options.stages.has(Stage::kBarnet));
  EXPECT_TRUE(back.options.stages.has(Stage::kAnatomy));
  EXPECT_FALSE(back.options.sph.tresca);
  EXPECT_EQ(back.options.anatomy.skin_iterations, 7u);
  EXPECT_FALSE(back.options.sph.joint_measured);
  // A measured-joint run says so (and only then: older descriptions stay as they were).
  EXPECT_EQ(fw::encode_run_description(run).find("sph_joint_measured"), std::string::npos);
  run.options.sph.joint_measured = true;
  ASSERT_TRUE(fw::parse_run_description(fw::encode_run_description(run), &back, &error)) << error;
  EXPECT_TRUE(back.options.sph.joint_measured);
  // The dynamic skin's anchor cap too, when not the default.
  EXPECT_EQ(back.options.anatomy.skin_max_anchor_acceleration, 500u);
  EXPECT_EQ(fw::encode_run_description(run).find("skin_max_anchor_acceleration"), std::string::npos);
  run.options.anatomy.skin_max_anchor_acceleration = 0;
  ASSERT_TRUE(fw::parse_run_description(fw::encode_run_description(run), &back, &error)) << error;
  EXPECT_EQ(back.options.anatomy.skin_max_anchor_acceleration, 0u);
}

TEST(RunDescription, RefusesWhatItCannotReproduce) {
  fw::RunDescription run;
  run.options.tick_hz = 500;
  const std::string good = fw::encode_run_description(run);
  fw::RunDescription back;
  std::string error;
  const auto refused = [&](const std::string& text) {
    error.clear();
    return !fw::parse_run_description(text, &back, &error);
  };
  EXPECT_TRUE(refused(""));
  EXPECT_TRUE(refused("sinew-recording 2\n"));
  EXPECT_NE(error.find("not a sinew recording"), std::string::npos) << error;
  EXPECT_TRUE(refused(good + "colour = blue\n"));
  EXPECT_NE(error.find("unknown key 'colour'"), std::string::npos) << error;
  std::string no_rate = good;
  no_rate.replace(no_rate.find("tick_hz = 500"), 13, "tick_hz = 0");
  EXPECT_TRUE(refused(no_rate));
  EXPECT_NE(error.find("bad value for tick_hz"), std::string::npos) << error;
  std::string missing = good;
  missing.erase(missing.find("tresca"), missing.find('\n', missing.find("tresca")) - missing.find("tresca") + 1);
  EXPECT_TRUE(refused(missing));
  EXPECT_NE(error.find("lacks a key"), std::string::npos) << error;
  std::string bad_flag = good;
  bad_flag.replace(bad_flag.find("sph = true"), 10, "sph = yes!");
  EXPECT_TRUE(refused(bad_flag));
  EXPECT_NE(error.find("line"), std::string::npos) << error;
}
