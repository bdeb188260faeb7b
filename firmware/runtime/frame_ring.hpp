// A single-producer, single-consumer ring of pose-frame slots, every slot's
// arrays allocated once at init from the frame's dimensions. The tick thread
// copies its frame into the next free slot and publishes it with one release
// store; the I/O thread reads slots in order and releases them. Neither side
// ever takes a lock or allocates; a full ring refuses the frame (the caller
// counts it). Head and tail count frames since init (64-bit: they never wrap
// in practice); a slot is index % capacity.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hal/common/pose_frame.hpp"

namespace sinew::firmware {

struct FrameDims {
  uint32_t vertex_count = 0;
  uint32_t input_count = 0;
  bool normals = false;      // slots hold normals (copied when the frame has them)
  uint32_t stage_count = 0;  // slots hold this many stage times (a frame's extra ones are left out)
};

class FrameRing {
 public:
  // capacity >= 1 slots of `dims`. Allocates; call before the loop starts.
  void init(size_t capacity, const FrameDims& dims);

  // Producer: copies `frame` into the next slot and publishes it. False when
  // the ring is full or the frame is larger than the slots (nothing copied).
  bool try_push(const hal::PoseFrame& frame);

  // Consumer: the oldest published frame, or nullptr when empty. It stays
  // valid (and unchanged) until pop().
  const hal::PoseFrame* front();
  void pop();

  size_t capacity() const { return slots_.size(); }
  size_t size() const {
    return static_cast<size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire));
  }
  bool empty() const { return size() == 0; }
  // Atomics the sides wait on (std::atomic::wait): the producer's count of
  // published frames and the consumer's count of released ones.
  std::atomic<uint64_t>& head() { return head_; }
  std::atomic<uint64_t>& tail() { return tail_; }

 private:
  struct Slot {
    hal::PoseFrame frame;  // points into the vectors below
    std::vector<int32_t> position[3], normal[3], input_value;
    std::vector<uint8_t> input_status;
    std::vector<uint32_t> stage_ns;
  };
  std::vector<Slot> slots_;
  FrameDims dims_;
  // Each counter on its own cache line: the two threads write one each.
  alignas(64) std::atomic<uint64_t> head_{0};
  alignas(64) std::atomic<uint64_t> tail_{0};
};

}  // namespace sinew::firmware
