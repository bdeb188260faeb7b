// The parser must survive any input: every truncation of a valid file and
// many random corruptions either parse into consistent data or fail with a
// line-numbered message. (A coverage-guided fuzzer can reuse parse_bvh as is.)
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "host_tools/motion/bvh.hpp"

namespace sinew::motion {
namespace {

const std::string kSeed =
    "HIERARCHY\r\nROOT Hips\n{\r  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation "
    "Xrotation "
    "Yrotation\n  JOINT Chest\n  {\n    OFFSET 0 5 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    End Site\n    {\n      OFFSET 0 4 0\n    }\n  }\n  JOINT Leg { OFFSET 1 -3 0 CHANNELS 1 Xrotation "
    "}\n}\n"
    "MOTION\nFrames: 2\nFrame Time: 0.0333333\n0 90 0 0 0 0 0 0 0 5\r\n1 90 0 10 20 30 40 50 60 -5\n";

void expect_consistent(const std::string& text) {
  Bvh bvh;
  std::string error;
  if (!parse_bvh(text, &bvh, &error)) {
    EXPECT_EQ(error.rfind("line ", 0), 0u) << error;
    return;
  }
  EXPECT_FALSE(bvh.joints.empty());
  EXPECT_EQ(bvh.values.size(), bvh.frame_count * bvh.channel_count);
  size_t channels = 0;
  for (size_t j = 0; j < bvh.joints.size(); ++j) {
    EXPECT_LT(bvh.joints[j].parent, static_cast<int>(j));
    EXPECT_LE(bvh.joints[j].channels.size(), 6u);
    EXPECT_LE(bvh.joints[j].first_value + bvh.joints[j].channels.size(), bvh.channel_count);
    channels += bvh.joints[j].channels.size();
  }
  EXPECT_EQ(channels, bvh.channel_count);
}

TEST(BvhRobustness, SeedParses) {
  Bvh bvh;
  std::string error;
  ASSERT_TRUE(parse_bvh(kSeed, &bvh, &error)) << error;
  EXPECT_EQ(bvh.joints.size(), 3u);
  EXPECT_EQ(bvh.channel_count, 10u);
}

TEST(BvhRobustness, EveryTruncation) {
  for (size_t n = 0; n <= kSeed.size(); ++n) expect_consistent(kSeed.substr(0, n));
}

TEST(BvhRobustness, RandomCorruptions) {
  std::mt19937 rng(20240611);  // fixed seed: the same inputs on every run
  using namespace std::string_literals;
  const std::string alphabet = " \t\r\n{}-+.eE0123456789:xyzXYZ#\0\xFF"s;
  for (int round = 0; round < 20000; ++round) {
    std::string text = kSeed;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = rng() % (text.size() + 1);
      const char c = alphabet[rng() % alphabet.size()];
      switch (rng() % 3) {
        case 0:
          if (at < text.size()) text[at] = c;
          break;
        case 1:
          text.insert(at, 1, c);
          break;
        default:
          if (at < text.size()) text.erase(at, 1 + rng() % 8);
          break;
      }
    }
    expect_consistent(text);
  }
}

TEST(BvhRobustness, DeepNestingAndHugeCounts) {
  std::string deep = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\n";
  for (int i = 0; i < 100000; ++i) deep += "JOINT j {\nOFFSET 0 0 0\n";
  Bvh bvh;
  std::string error;
  EXPECT_FALSE(parse_bvh(deep, &bvh, &error));
  EXPECT_NE(error.find("missing '}'"), std::string::npos) << error;

  const std::string huge =
      "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\n"
      "Frames: 18446744073709551615\nFrame Time: 1\n0\n";
  EXPECT_FALSE(parse_bvh(huge, &bvh, &error));
  EXPECT_NE(error.find("file ends after 1 of the 18446744073709551615 frames"), std::string::npos) << error;
  EXPECT_FALSE(parse_bvh(huge.substr(0, huge.find("Frames")) + "Frames: 99999999999999999999\n", &bvh, &error));
  EXPECT_NE(error.find("too large"), std::string::npos) << error;
}

}  // namespace
}  // namespace sinew::motion
