// Line endings (\n, \r\n, lone \r, mixed in one file), tabs and extra
// whitespace must not change what a BVH file means, nor the line numbers in
// its error messages.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host_tools/motion/bvh.hpp"

namespace sinew::motion {
namespace {

// One statement per entry; joined with the line ending under test.
const std::vector<std::string> kLines = {
    "HIERARCHY",
    "ROOT Pelvis",
    "{",
    "\tOFFSET\t0.5  -1\t\t2 ",
    "  CHANNELS 3   Xposition Yposition Zposition",
    "\t JOINT  Left Knee ",
    "\t{",
    "\t\tOFFSET 0 -4.25 0",
    "\t\tCHANNELS 2 Xrotation Zrotation",
    "\t\tEnd Site",
    "\t\t{",
    "\t\t\tOFFSET 0 -4 0",
    "\t\t}",
    "\t}",
    "}",
    "MOTION",
    "Frames:\t2",
    "Frame Time:   0.5",
    "1 2 3 4 5",
    "",
    " \t-1\t-2 -3   -4 -5.5\t",
};

std::string join(const std::vector<std::string>& lines, const std::vector<std::string>& endings) {
  std::string text;
  for (size_t i = 0; i < lines.size(); ++i) text += lines[i] + endings[i % endings.size()];
  return text;
}

void expect_same(const Bvh& a, const Bvh& b) {
  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (size_t j = 0; j < a.joints.size(); ++j) {
    EXPECT_EQ(a.joints[j].name, b.joints[j].name);
    EXPECT_EQ(a.joints[j].parent, b.joints[j].parent);
    EXPECT_EQ(a.joints[j].offset, b.joints[j].offset);
    EXPECT_EQ(a.joints[j].channels, b.joints[j].channels);
  }
  EXPECT_EQ(a.end_sites.size(), b.end_sites.size());
  EXPECT_EQ(a.frame_count, b.frame_count);
  EXPECT_EQ(a.frame_time, b.frame_time);
  EXPECT_EQ(a.values, b.values);
}

TEST(BvhLineEndings, EveryStyleAndMixturesParseAlike) {
  Bvh reference;
  std::string error;
  ASSERT_TRUE(parse_bvh(join(kLines, {"\n"}), &reference, &error)) << error;
  EXPECT_EQ(reference.joints[1].name, "Left Knee");
  EXPECT_EQ(reference.joints[0].offset, (Vec3{0.5, -1, 2}));
  EXPECT_EQ(reference.values, (std::vector<double>{1, 2, 3, 4, 5, -1, -2, -3, -4, -5.5}));

  const std::vector<std::vector<std::string>> styles = {
      {"\r\n"}, {"\r"}, {"\n", "\r\n"}, {"\r", "\n", "\r\n"}, {"\r\n", "\r"}};
  for (const auto& endings : styles) {
    Bvh parsed;
    const std::string text = join(kLines, endings);
    ASSERT_TRUE(parse_bvh(text, &parsed, &error)) << error;
    expect_same(reference, parsed);
  }
}

TEST(BvhLineEndings, NoFinalLineEndingAndUtf8Bom) {
  std::string text = "\xEF\xBB\xBF" + join(kLines, {"\r\n"});
  text.resize(text.size() - 2);
  Bvh parsed;
  std::string error;
  ASSERT_TRUE(parse_bvh(text, &parsed, &error)) << error;
  EXPECT_EQ(parsed.frame_count, 2u);
}

TEST(BvhLineEndings, ErrorLineNumbersCountEveryEndingStyle) {
  std::vector<std::string> lines = kLines;
  lines[11] = "\t\t\tOFFSET 0 -4 zero";  // line 12
  for (const auto& endings : std::vector<std::vector<std::string>>{{"\n"}, {"\r"}, {"\r\n", "\r", "\n"}}) {
    Bvh parsed;
    std::string error;
    ASSERT_FALSE(parse_bvh(join(lines, endings), &parsed, &error));
    EXPECT_NE(error.find("line 12:"), std::string::npos) << error;
    EXPECT_NE(error.find("'zero' is not a number"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace sinew::motion
