// Synthetic pose frames for the output tests: owned arrays whose contents
// depend on (tick, index), so every frame and every value differs.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hal/common/pose_frame.hpp"
#include "hal/output/frame_shape.hpp"
#include "hal/output/pose_decode.hpp"

namespace sinew::test {

inline int32_t mixed_value(uint64_t tick, uint64_t index, uint64_t salt) {
  uint64_t z = tick * 0x9E3779B97F4A7C15ull + index * 0xBF58476D1CE4E5B9ull + salt * 0x94D049BB133111EBull;
  z ^= z >> 31;
  z *= 0xD6E8FEB86CA776C5ull;
  z ^= z >> 29;
  return static_cast<int32_t>(static_cast<uint32_t>(z));
}

class TestPose {
 public:
  TestPose(uint32_t vertex_count, uint32_t input_count, bool normals, int32_t length_exponent = -3)
      : normals_(normals) {
    for (auto& a : position_) a.resize(vertex_count);
    for (auto& a : normal_) a.resize(normals ? vertex_count : 0);
    value_.resize(input_count);
    status_.resize(input_count);
    frame_.length_exponent = length_exponent;
    frame_.vertex_count = vertex_count;
    frame_.input_count = input_count;
    for (int c = 0; c < 3; ++c) {
      frame_.position[c] = position_[c].data();
      frame_.normal[c] = normals ? normal_[c].data() : nullptr;
    }
    frame_.input_value = value_.data();
    frame_.input_status = status_.data();
    set_tick(0);
  }

  // Fills every array with values unique to `tick` (no allocation).
  void set_tick(uint64_t tick) {
    frame_.tick = tick;
    frame_.timestamp_ns = 1'000'000'000ull + tick * 1'000'000ull;
    for (size_t c = 0; c < 3; ++c)
      for (size_t v = 0; v < position_[c].size(); ++v) {
        position_[c][v] = mixed_value(tick, v, c);
        if (normals_) normal_[c][v] = mixed_value(tick, v, c + 3);
      }
    for (size_t i = 0; i < value_.size(); ++i) {
      value_[i] = mixed_value(tick, i, 7);
      status_[i] = static_cast<uint8_t>((tick + i) & 0x0F);
    }
  }

  const hal::PoseFrame& frame() const { return frame_; }
  hal::output::FrameShape shape() const { return hal::output::shape_of(frame_); }

 private:
  bool normals_;
  std::vector<int32_t> position_[3], normal_[3], value_;
  std::vector<uint8_t> status_;
  hal::PoseFrame frame_;
};

// Field-by-field equality of a decoded pose and the frame it came from.
inline void expect_same_pose(const hal::output::DecodedPose& got, const hal::PoseFrame& want, bool normals) {
  EXPECT_EQ(got.tick, want.tick);
  EXPECT_EQ(got.timestamp_ns, want.timestamp_ns);
  EXPECT_EQ(got.length_exponent, want.length_exponent);
  ASSERT_EQ(got.vertex_count, want.vertex_count);
  ASSERT_EQ(got.input_count, want.input_count);
  ASSERT_EQ(got.has_normals, normals);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(got.position[c], std::vector<int32_t>(want.position[c], want.position[c] + want.vertex_count));
    if (normals) {
      EXPECT_EQ(got.normal[c], std::vector<int32_t>(want.normal[c], want.normal[c] + want.vertex_count));
    }
  }
  EXPECT_EQ(got.input_value, std::vector<int32_t>(want.input_value, want.input_value + want.input_count));
  EXPECT_EQ(got.input_status, std::vector<uint8_t>(want.input_status, want.input_status + want.input_count));
}

}  // namespace sinew::test
