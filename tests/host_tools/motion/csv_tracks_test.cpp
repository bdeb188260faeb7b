// CSV joint tracks: parsing, comments and line endings, interpolation and
// clamping, and errors that name line and column.
#include "host_tools/motion/csv_tracks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace sinew::motion {
namespace {

const std::string kTracks =
    "# elbow and wrist, degrees\r\n"
    "\r\n"
    "time,elbow.flex,wrist.twist\r\n"
    "0.0, 10, 0\r\n"
    "# a pause in the recording\n"
    "0.5, 45,-5.5\r"
    "1.5 ,45 , 14.5\n";

JointTracks parse_ok(const std::string& text) {
  JointTracks tracks;
  std::string error;
  EXPECT_TRUE(parse_csv_tracks(text, &tracks, &error)) << error;
  return tracks;
}

TEST(CsvTracks, ParsesHeaderRowsCommentsAndMixedLineEndings) {
  const JointTracks tracks = parse_ok(kTracks);
  ASSERT_EQ(tracks.tracks.size(), 2u);
  EXPECT_EQ(tracks.tracks[0].joint, "elbow");
  EXPECT_EQ(tracks.tracks[0].dof, "flex");
  EXPECT_EQ(tracks.tracks[1].joint, "wrist");
  EXPECT_EQ(tracks.tracks[1].dof, "twist");
  EXPECT_EQ(tracks.times, (std::vector<double>{0.0, 0.5, 1.5}));
  EXPECT_EQ(tracks.values, (std::vector<double>{10, 0, 45, -5.5, 45, 14.5}));
  EXPECT_EQ(tracks.find("wrist", "twist"), 1u);
  EXPECT_FALSE(tracks.find("wrist", "flex").has_value());
}

TEST(CsvTracks, JointNamesMayContainDots) {
  const JointTracks tracks = parse_ok("time,hand.l.index.flex\n0,1\n");
  EXPECT_EQ(tracks.tracks[0].joint, "hand.l.index");
  EXPECT_EQ(tracks.tracks[0].dof, "flex");
}

TEST(CsvTracks, InterpolatesLinearlyAndClampsAtTheEnds) {
  const JointTracks tracks = parse_ok(kTracks);
  EXPECT_DOUBLE_EQ(sample_track(tracks, 0, 0.25), 27.5);
  EXPECT_DOUBLE_EQ(sample_track(tracks, 1, 0.25), -2.75);
  EXPECT_DOUBLE_EQ(sample_track(tracks, 1, 1.0), 4.5);
  EXPECT_DOUBLE_EQ(sample_track(tracks, 0, 1.0), 45);
  // Exactly at samples.
  EXPECT_EQ(sample_tracks(tracks, 0.5), (std::vector<double>{45, -5.5}));
  EXPECT_EQ(sample_tracks(tracks, 1.5), (std::vector<double>{45, 14.5}));
  // Clamped outside, and NaN held at the start.
  EXPECT_EQ(sample_tracks(tracks, -3), (std::vector<double>{10, 0}));
  EXPECT_EQ(sample_tracks(tracks, 99), (std::vector<double>{45, 14.5}));
  EXPECT_EQ(sample_tracks(tracks, std::numeric_limits<double>::infinity()), (std::vector<double>{45, 14.5}));
  EXPECT_EQ(sample_tracks(tracks, std::nan("")), (std::vector<double>{10, 0}));
  EXPECT_THROW(sample_track(tracks, 2, 0), std::out_of_range);
}

TEST(CsvTracks, SingleSampleIsConstant) {
  const JointTracks tracks = parse_ok("time,a.x\n2,7\n");
  EXPECT_EQ(sample_track(tracks, 0, 0), 7);
  EXPECT_EQ(sample_track(tracks, 0, 2), 7);
  EXPECT_EQ(sample_track(tracks, 0, 5), 7);
}

struct BadCsv {
  const char* what;
  const char* text;
  const char* where;  // "line N, column C:" or "line N:"
  const char* phrase;
};

TEST(CsvTracks, ErrorsNameLineAndColumn) {
  const std::vector<BadCsv> cases = {
      {"empty", "", "line 1:", "no header"},
      {"only comments", "# nothing\n\n", "line 1:", "no header"},
      {"first column not time", "t,a.x\n0,1\n", "line 1, column 1:", "must be 'time', found 't'"},
      {"no tracks", "time\n0\n", "line 1:", "names no joint tracks"},
      {"track without dof", "time,elbow\n0,1\n", "line 1, column 2:", "'elbow' is not a track name"},
      {"track with empty joint", "time,a.x,.x\n0,1,2\n", "line 1, column 3:", "'.x' is not a track name"},
      {"track with a space", "time,left elbow.flex\n0,1\n", "line 1, column 2:", "is not a track name"},
      {"duplicate track", "time,a.x,b.y,a.x\n0,1,2,3\n", "line 1, column 4:", "'a.x' appears twice"},
      {"no samples", "time,a.x\n# none\n", "line 1:", "no samples"},
      {"missing value", "time,a.x,b.y\n0,1,2\n1,1\n", "line 3, column 3:", "missing value for 'b.y'"},
      {"extra value", "time,a.x\n0,1,2\n", "line 2, column 3:", "extra field"},
      {"empty value", "time,a.x,b.y\n0,,2\n", "line 2, column 2:", "empty value for 'a.x'"},
      {"non-numeric", "time,a.x,b.y\r\n0,1,2\r\n1,2,abc\r\n", "line 3, column 3:", "b.y: 'abc' is not a number"},
      {"nan", "time,a.x\n0,nan\n", "line 2, column 2:", "'nan' is not a finite number"},
      {"inf time", "time,a.x\ninf,1\n", "line 2, column 1:", "'inf' is not a finite number"},
      {"time not increasing", "time,a.x\n0,1\n# c\n0.5,2\n0.5,3\n",
       "line 5, column 1:", "time 0.5 is not after the previous sample's (line 4)"},
      {"time decreasing", "time,a.x\n1,1\n0,2\n", "line 3, column 1:", "is not after"},
  };
  for (const BadCsv& bad : cases) {
    JointTracks tracks;
    std::string error;
    EXPECT_FALSE(parse_csv_tracks(bad.text, &tracks, &error)) << bad.what;
    EXPECT_EQ(error.rfind(bad.where, 0), 0u) << bad.what << ": " << error;
    EXPECT_NE(error.find(bad.phrase), std::string::npos) << bad.what << ": " << error;
    EXPECT_TRUE(tracks.tracks.empty() && tracks.times.empty()) << bad.what;
  }
}

TEST(CsvTracks, LoadNamesTheFile) {
  JointTracks tracks;
  std::string error;
  EXPECT_FALSE(load_csv_tracks(std::string(SINEW_TEST_DATA_DIR) + "/no-such-tracks.csv", &tracks, &error));
  EXPECT_NE(error.find("no-such-tracks.csv: cannot open"), std::string::npos) << error;
}

}  // namespace
}  // namespace sinew::motion
