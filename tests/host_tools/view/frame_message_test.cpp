// The viewer's frame message (host_tools/view/frame_message.hpp) against the
// pose payload it encodes: the layout (length-prefixed JSON, float32 arrays
// whose sizes fill the message exactly), positions in metres as
// docs/frame-formats.md defines them (Q12.20 rig units x 2^e), and the
// rig/stream mismatch named instead of a frame.
#include "host_tools/view/frame_message.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "host_tools/view/json_text.hpp"

namespace {

using sinew::hal::output::DecodedPose;
using sinew::view::ViewRig;

ViewRig load_arm_for_view_test() {
  ViewRig rig;
  std::string error;
  EXPECT_TRUE(sinew::view::load_view_rig("arm", &rig, &error)) << error;
  return rig;
}

// The rig's rest pose as a frame, one vertex moved by a known amount.
DecodedPose rest_frame_for_view_test(const ViewRig& rig) {
  const auto& r = rig.loaded.rig;
  DecodedPose pose;
  pose.tick = 7;
  pose.length_exponent = r.length_exponent;
  pose.vertex_count = r.vertex_count();
  pose.input_count = rig.loaded.input_count();
  for (int c = 0; c < 3; ++c) pose.position[c].assign(r.position[c].begin(), r.position[c].end());
  pose.input_value.assign(pose.input_count, 0);
  pose.input_status.assign(pose.input_count, 0);
  return pose;
}

std::string message_json_for_view_test(const std::vector<uint8_t>& m) {
  uint32_t n = 0;
  for (int b = 0; b < 4; ++b) n |= uint32_t{m[static_cast<size_t>(b)]} << (8 * b);
  return std::string(reinterpret_cast<const char*>(m.data()) + 4, n);
}

}  // namespace

TEST(ViewFrameMessage, PositionsAreTheFramesInMetresAndTheArraysFillTheMessage) {
  const ViewRig rig = load_arm_for_view_test();
  DecodedPose pose = rest_frame_for_view_test(rig);
  pose.position[0][5] += 1 << 20;  // one rig unit along x
  sinew::view::ShadowPipeline shadow;
  std::string error;
  ASSERT_TRUE(shadow.init(rig, {}, &error)) << error;
  shadow.step_frame(pose);  // rest inputs: plain skinning gives the rest pose
  const std::deque<sinew::view::ShadowStep> history;
  const auto m = sinew::view::frame_message(rig, pose, &shadow, history, 1000000, {}, {}, "");
  const std::string json = message_json_for_view_test(m);
  const size_t floats_at = (4 + json.size() + 3) / 4 * 4;
  const size_t v = pose.vertex_count;
  ASSERT_NE(json.find("[\"position\"," + std::to_string(3 * v) + "]"), std::string::npos) << json.substr(0, 400);
  ASSERT_NE(json.find("[\"displacement\"," + std::to_string(v) + "]"), std::string::npos);
  ASSERT_EQ(json.find("\"error\""), std::string::npos);
  ASSERT_EQ(json.find("\"normal\""), std::string::npos) << "the frame has no normals";
  // position first: x, y, z of vertex k at 3k.
  auto float_at = [&](size_t index) {
    float f;
    std::memcpy(&f, m.data() + floats_at + 4 * index, 4);
    return static_cast<double>(f);
  };
  const double unit_m = std::ldexp(1.0, pose.length_exponent);
  for (size_t k : {size_t{0}, size_t{5}, v - 1})
    for (int c = 0; c < 3; ++c) {
      const double want = std::ldexp(static_cast<double>(pose.position[c][k]), pose.length_exponent - 20);
      EXPECT_NEAR(float_at(3 * k + static_cast<size_t>(c)), want, std::abs(want) * 1e-6 + 1e-9);
    }
  // The displacement from plain skinning is the moved vertex's one rig unit
  // (the skin at rest inputs is the rest pose within rounding: Q12.20 steps).
  const double step_m = unit_m / (1 << 20);
  EXPECT_NEAR(float_at(3 * v + 5), unit_m, 4 * step_m + unit_m * 1e-6);
  EXPECT_LT(float_at(3 * v + 0), 4 * step_m);
}

TEST(ViewFrameMessage, AStreamOfAnotherShapeIsNamedNotDrawn) {
  const ViewRig rig = load_arm_for_view_test();
  DecodedPose pose = rest_frame_for_view_test(rig);
  EXPECT_EQ(sinew::view::rig_stream_mismatch(rig, pose), "");
  pose.vertex_count -= 1;
  const std::string why = sinew::view::rig_stream_mismatch(rig, pose);
  EXPECT_NE(why.find(std::to_string(pose.vertex_count) + " vertices"), std::string::npos) << why;
  EXPECT_NE(why.find(std::to_string(rig.loaded.rig.vertex_count())), std::string::npos) << why;
  const auto m = sinew::view::frame_message(rig, pose, nullptr, {}, 1000000, {}, {}, why);
  const std::string json = message_json_for_view_test(m);
  EXPECT_NE(json.find("\"error\":\"rig/stream mismatch"), std::string::npos) << json.substr(0, 400);
  EXPECT_NE(json.find("\"arrays\":[]"), std::string::npos) << "no surface is sent for a mismatched frame";
  pose.vertex_count += 1;
  pose.input_count += 1;
  EXPECT_NE(sinew::view::rig_stream_mismatch(rig, pose).find("inputs"), std::string::npos);
}

TEST(ViewJsonText, EscapesStringsAndSeparatesValues) {
  sinew::view::JsonText j;
  j.open_object().key("a").string("q\"\\\n").key("b").open_array().number(int64_t{1}).number(2.5).close_array();
  j.close_object();
  EXPECT_EQ(j.take(), "{\"a\":\"q\\\"\\\\\\u000a\",\"b\":[1,2.5]}");
}
