// A small frame log written once per test (5 frames of a 10-vertex mesh,
// normals on all but one frame) with its record boundaries, and a helper
// that reads any log back completely.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "hal/output/frame_log_reader.hpp"
#include "hal/output/frame_log_writer.hpp"
#include "temp_dir.hpp"
#include "test_poses.hpp"

namespace sinew::test {

struct ReadBack {
  bool opened = false;
  std::string error;
  std::vector<hal::output::DecodedPose> poses;
  hal::output::LogStop stop = hal::output::LogStop::kNone;
  uint64_t stop_offset = 0;
  uint64_t discarded = 0;
};

inline ReadBack read_log(const std::string& path) {
  ReadBack r;
  hal::output::FrameLogReader reader;
  r.opened = reader.open(path, &r.error);
  if (!r.opened) return r;
  hal::output::DecodedPose pose;
  while (reader.next(&pose)) r.poses.push_back(pose);
  r.stop = reader.stop();
  r.stop_offset = reader.stop_offset();
  r.discarded = reader.discarded_bytes();
  return r;
}

class FrameLogTest : public testing::Test {
 protected:
  static constexpr uint32_t kVertices = 10;
  static constexpr uint32_t kInputs = 3;
  static constexpr uint64_t kFrames = 5;
  static constexpr uint64_t kFrameWithoutNormals = 2;

  FrameLogTest() : shape_(TestPose(kVertices, kInputs, true).shape()) {
    for (uint64_t t = 0; t < kFrames; ++t) {
      poses_.push_back(std::make_unique<TestPose>(kVertices, kInputs, t != kFrameWithoutNormals));
      poses_.back()->set_tick(t);
    }
  }

  // Writes frames [first, last) to `path`, returning the file size after each record.
  std::vector<uint64_t> write_frames(const std::string& path, uint64_t first, uint64_t last,
                                     hal::output::FrameLogOptions options = {}) {
    hal::output::FrameLogWriter writer;
    std::string error;
    std::vector<uint64_t> ends;
    EXPECT_TRUE(writer.open(path, shape_, options, &error)) << error;
    for (uint64_t t = first; t < last; ++t) {
      EXPECT_TRUE(writer.write(poses_[t]->frame()));
      ends.push_back(writer.file_bytes());
    }
    return ends;
  }

  void expect_frames(const std::vector<hal::output::DecodedPose>& got, size_t count) {
    ASSERT_EQ(got.size(), count);
    for (size_t i = 0; i < count; ++i) expect_same_pose(got[i], poses_[i]->frame(), i != kFrameWithoutNormals);
  }

  TempDir dir_;
  hal::output::FrameShape shape_;
  std::vector<std::unique_ptr<TestPose>> poses_;
};

}  // namespace sinew::test
