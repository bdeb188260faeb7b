#include "frame_ring.hpp"

#include <algorithm>

namespace sinew::firmware {

namespace {

template <typename T>
void copy_array(const T* from, size_t count, std::vector<T>* to) {
  if (count > 0) std::copy(from, from + count, to->begin());
}

}  // namespace

void FrameRing::init(size_t capacity, const FrameDims& dims) {
  dims_ = dims;
  slots_.clear();
  slots_.resize(std::max<size_t>(capacity, 1));
  for (Slot& s : slots_) {
    for (int c = 0; c < 3; ++c) {
      s.position[c].assign(dims.vertex_count, 0);
      if (dims.normals) s.normal[c].assign(dims.vertex_count, 0);
    }
    s.input_value.assign(dims.input_count, 0);
    s.input_status.assign(dims.input_count, 0);
    s.stage_ns.assign(dims.stage_count, 0);
  }
  head_.store(0, std::memory_order_relaxed);
  tail_.store(0, std::memory_order_relaxed);
}

bool FrameRing::try_push(const hal::PoseFrame& frame) {
  if (frame.vertex_count > dims_.vertex_count || frame.input_count > dims_.input_count) return false;
  const uint64_t head = head_.load(std::memory_order_relaxed);
  // Acquire: the consumer is done reading the slot it released.
  if (head - tail_.load(std::memory_order_acquire) >= slots_.size()) return false;
  Slot& s = slots_[head % slots_.size()];
  hal::PoseFrame& f = s.frame;
  f = frame;
  const bool normals = dims_.normals && frame.normal[0] && frame.normal[1] && frame.normal[2];
  for (int c = 0; c < 3; ++c) {
    copy_array(frame.position[c], frame.vertex_count, &s.position[c]);
    f.position[c] = s.position[c].data();
    if (normals) copy_array(frame.normal[c], frame.vertex_count, &s.normal[c]);
    f.normal[c] = normals ? s.normal[c].data() : nullptr;
  }
  copy_array(frame.input_value, frame.input_count, &s.input_value);
  copy_array(frame.input_status, frame.input_count, &s.input_status);
  f.input_value = s.input_value.data();
  f.input_status = s.input_status.data();
  f.stage_count = std::min(frame.stage_ns != nullptr ? frame.stage_count : 0u, dims_.stage_count);
  copy_array(frame.stage_ns, f.stage_count, &s.stage_ns);
  f.stage_ns = f.stage_count > 0 ? s.stage_ns.data() : nullptr;
  // Release: the slot's contents are visible before the consumer sees it.
  head_.store(head + 1, std::memory_order_seq_cst);
  return true;
}

const hal::PoseFrame* FrameRing::front() {
  const uint64_t tail = tail_.load(std::memory_order_relaxed);
  if (head_.load(std::memory_order_acquire) == tail) return nullptr;
  return &slots_[tail % slots_.size()].frame;
}

void FrameRing::pop() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_seq_cst); }

}  // namespace sinew::firmware
