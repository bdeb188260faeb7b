// What every frame decoder (default joint stream, configured DBC signals)
// produces from one received frame: accepted samples and rejections, in a
// fixed-size result; plus per-input counters kept by the common base.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "can_frame.hpp"
#include "hal/common/joint_sample.hpp"

namespace sinew::hal::can {

inline constexpr size_t kMaxSamplesPerFrame = 32;
inline constexpr size_t kRejectReasonCount = static_cast<size_t>(RejectReason::kCount);
inline constexpr int32_t kNoInput = -1;

struct Rejection {
  int32_t input = kNoInput;  // rig input the rejected data was for, kNoInput if none (unknown ID)
  RejectReason reason = RejectReason::kMalformed;
};

struct FrameDecode {
  uint8_t sample_count = 0;
  uint8_t rejection_count = 0;
  std::array<JointSample, kMaxSamplesPerFrame> samples{};
  std::array<Rejection, kMaxSamplesPerFrame> rejections{};

  std::span<const JointSample> accepted() const { return {samples.data(), sample_count}; }
  std::span<const Rejection> rejected() const { return {rejections.data(), rejection_count}; }
  void add_sample(const JointSample& s) { samples[sample_count++] = s; }
  void add_rejection(int32_t input, RejectReason reason) { rejections[rejection_count++] = {input, reason}; }
};

// A configured input as far as receive timeouts and kernel filters are concerned.
struct ChannelInfo {
  uint16_t input = 0;
  uint64_t timeout_ns = 0;  // resolved; 0 = never stale
};

struct FrameId {
  uint32_t id = 0;
  bool extended = false;
  bool operator==(const FrameId&) const = default;
};

struct ChannelCounters {
  uint64_t accepted = 0;
  std::array<uint64_t, kRejectReasonCount> rejected{};
  uint64_t rejected_total() const;
};

class FrameDecoder {
 public:
  virtual ~FrameDecoder() = default;

  // Decodes one frame into `out` (cleared first) and counts the outcome.
  // Error frames produce nothing: bus state belongs to the frame source.
  void decode(const CanFrame& frame, FrameDecode& out);

  virtual std::span<const ChannelInfo> channels() const = 0;
  virtual std::span<const FrameId> frame_ids() const = 0;
  virtual bool wants_fd() const = 0;  // some configured frame is CAN FD

  // Counters of one input (zeroes for an input this decoder does not feed),
  // and of rejections that belong to no input.
  const ChannelCounters& counters(uint16_t input) const;
  const ChannelCounters& unassigned() const { return unassigned_; }

 protected:
  virtual void decode_frame(const CanFrame& frame, FrameDecode& out) = 0;
  // Called by configure() of the derived class once its inputs are known.
  void size_counters(std::span<const ChannelInfo> channels);

 private:
  std::vector<ChannelCounters> by_input_;
  ChannelCounters unassigned_;
  ChannelCounters zero_;
};

}  // namespace sinew::hal::can
