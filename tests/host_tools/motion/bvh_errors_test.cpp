// Every kind of malformed BVH is refused with a message naming the line and
// the problem.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host_tools/motion/bvh.hpp"

namespace sinew::motion {
namespace {

// A valid file; each case below changes it a little.
const std::string kValid =
    "HIERARCHY\n"                                                                 // 1
    "ROOT Hips\n"                                                                 // 2
    "{\n"                                                                         // 3
    "  OFFSET 0 0 0\n"                                                            // 4
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"  // 5
    "  JOINT Chest\n"                                                             // 6
    "  {\n"                                                                       // 7
    "    OFFSET 0 5 0\n"                                                          // 8
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"                              // 9
    "    End Site\n"                                                              // 10
    "    {\n"                                                                     // 11
    "      OFFSET 0 4 0\n"                                                        // 12
    "    }\n"                                                                     // 13
    "  }\n"                                                                       // 14
    "}\n"                                                                         // 15
    "MOTION\n"                                                                    // 16
    "Frames: 2\n"                                                                 // 17
    "Frame Time: 0.0333333\n"                                                     // 18
    "0 90 0 0 0 0 0 0 0\n"                                                        // 19
    "1 90 0 10 20 30 40 50 60\n";                                                 // 20

std::string replace(const std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string out = text;
  out.replace(at, from.size(), to);
  return out;
}

struct BadCase {
  const char* what;
  std::string text;
  int line;
  const char* phrase;
};

std::vector<BadCase> bad_cases() {
  return {
      {"empty file", "", 1, "expected HIERARCHY"},
      {"not a BVH", "hello\n", 1, "expected HIERARCHY, found 'hello'"},
      {"no root", "HIERARCHY\nMOTION\nFrames: 0\nFrame Time: 1\n", 2, "no ROOT"},
      {"truncated in the hierarchy", kValid.substr(0, kValid.find("  }\n}")), 13, "missing '}'"},
      {"truncated in the header", kValid.substr(0, kValid.find("Frame Time")), 17, "expected 'Frame Time:'"},
      {"truncated rows", kValid.substr(0, kValid.find("1 90")), 19, "file ends after 1 of the 2 frames"},
      {"missing opening brace", replace(kValid, "  JOINT Chest\n  {\n", "  JOINT Chest\n  OFFSET\n"), 7,
       "expected '{' after JOINT 'Chest'"},
      {"missing closing brace", replace(kValid, "  }\n}\nMOTION", "  }\nMOTION"), 15,
       "'MOTION' before the closing '}' of joint 'Hips'"},
      {"extra closing brace", replace(kValid, "}\nMOTION", "}\n}\nMOTION"), 16, "expected ROOT or MOTION, found '}'"},
      {"joint without a name", replace(kValid, "JOINT Chest", "JOINT"), 6, "JOINT without a name"},
      {"unknown channel", replace(kValid, "3 Zrotation Xrotation Yrotation", "3 Zrotation Xrotation Wrotation"), 9,
       "unknown channel 'Wrotation'"},
      {"too few channel names", replace(kValid, "3 Zrotation Xrotation Yrotation", "3 Zrotation Xrotation"), 9,
       "CHANNELS declares 3 channels but lists 2"},
      {"too many channel names", replace(kValid, "3 Zrotation Xrotation Yrotation", "2 Zrotation Xrotation Yrotation"),
       9, "CHANNELS declares 2 channels but lists more"},
      {"more than six channels", replace(kValid, "CHANNELS 6", "CHANNELS 7"), 5, "at most 6 channels"},
      {"non-numeric channel count", replace(kValid, "CHANNELS 6", "CHANNELS six"), 5, "CHANNELS count: 'six'"},
      {"repeated channel", replace(kValid, "3 Zrotation Xrotation Yrotation", "3 Zrotation Xrotation Zrotation"), 9,
       "channel Zrotation listed twice"},
      {"short OFFSET", replace(kValid, "OFFSET 0 5 0", "OFFSET 0 5"), 8, "OFFSET needs 3 numbers, found 2"},
      {"long OFFSET", replace(kValid, "OFFSET 0 5 0", "OFFSET 0 5 0 1"), 8, "OFFSET has more than 3 numbers"},
      {"no OFFSET", replace(kValid, "    OFFSET 0 5 0\n", ""), 13, "joint 'Chest' (line 6) has no OFFSET"},
      {"channels in an End Site", replace(kValid, "      OFFSET 0 4 0\n", "      CHANNELS 0\n"), 12,
       "End Site cannot have CHANNELS"},
      {"misspelt End Site", replace(kValid, "End Site", "End Sight"), 10, "expected 'End Site'"},
      {"stray word in a joint", replace(kValid, "    OFFSET 0 5 0\n", "    OFFSET 0 5 0\n    SCALE 2\n"), 9,
       "unexpected 'SCALE' in joint 'Chest'"},
      {"frame count too small", replace(kValid, "Frames: 2", "Frames: 1"), 20,
       "more frame rows than 'Frames: 1' declares (line 17)"},
      {"frame count too large", replace(kValid, "Frames: 2", "Frames: 3"), 20, "file ends after 2 of the 3 frames"},
      {"fractional frame count", replace(kValid, "Frames: 2", "Frames: 2.5"), 17, "Frames: '2.5'"},
      {"negative frame count", replace(kValid, "Frames: 2", "Frames: -2"), 17, "Frames: '-2'"},
      {"missing Frames", replace(kValid, "Frames: 2\n", ""), 17, "expected 'Frames:', found 'Frame'"},
      {"bad frame time", replace(kValid, "0.0333333", "fast"), 18, "Frame Time: 'fast' is not a number"},
      {"zero frame time", replace(kValid, "0.0333333", "0"), 18, "Frame Time must be positive"},
      {"too few values", replace(kValid, "1 90 0 10 20 30 40 50 60", "1 90 0 10 20 30 40 50"), 20,
       "frame 2 has 8 values, expected 9"},
      {"too many values", replace(kValid, "0 90 0 0 0 0 0 0 0", "0 90 0 0 0 0 0 0 0 0"), 19,
       "frame 1 has 10 values, expected 9"},
      {"non-numeric value", replace(kValid, "40 50 60", "40 5O 60"), 20,
       "value 8 (joint 'Chest' Xrotation): '5O' is not a number"},
      {"NaN value", replace(kValid, "40 50 60", "40 nan 60"), 20, "'nan' is not a finite number"},
      {"infinite value", replace(kValid, "10 20 30", "10 -inf 30"), 20, "'-inf' is not a finite number"},
      {"overflowing value", replace(kValid, "10 20 30", "10 1e999 30"), 20, "'1e999' is out of range"},
      {"NaN offset", replace(kValid, "OFFSET 0 4 0", "OFFSET 0 NaN 0"), 12, "'NaN' is not a finite number"},
      {"binary junk", replace(replace(kValid, "Chest", std::string("Ch\0\x01st", 6)), "50 60", "50 \x7F\xFF"), 20,
       "'\\x7F\\xFF' is not a number"},
  };
}

TEST(BvhErrors, EachMalformedInputNamesItsLineAndProblem) {
  for (const BadCase& bad : bad_cases()) {
    Bvh bvh;
    std::string error;
    EXPECT_FALSE(parse_bvh(bad.text, &bvh, &error)) << bad.what;
    const std::string line = "line " + std::to_string(bad.line) + ": ";
    EXPECT_EQ(error.rfind(line, 0), 0u) << bad.what << ": " << error;
    EXPECT_NE(error.find(bad.phrase), std::string::npos) << bad.what << ": " << error;
    EXPECT_TRUE(bvh.joints.empty() && bvh.values.empty()) << bad.what << ": no partial result";
  }
}

TEST(BvhErrors, TheValidBaseParses) {
  Bvh bvh;
  std::string error;
  ASSERT_TRUE(parse_bvh(kValid, &bvh, &error)) << error;
  EXPECT_EQ(bvh.frame_count, 2u);
  EXPECT_EQ(bvh.channel_count, 9u);
}

TEST(BvhErrors, LoadNamesTheFile) {
  Bvh bvh;
  std::string error;
  EXPECT_FALSE(load_bvh(std::string(SINEW_TEST_DATA_DIR) + "/no-such-file.bvh", &bvh, &error));
  EXPECT_NE(error.find("no-such-file.bvh: cannot open"), std::string::npos) << error;
}

}  // namespace
}  // namespace sinew::motion
