// Latest-value hand-off from one producer thread to one consumer thread,
// wait-free on both sides and allocation-free after construction.
//
// Three copies of T: the producer fills its private "back" copy and publishes
// it by swapping it with the shared "middle" one; the consumer, when the
// middle holds something fresh, swaps it with its private "front" copy. A swap
// is one atomic exchange of a small index word, so neither side ever waits for
// the other and the consumer never sees a half-written T. Intermediate values
// are overwritten, not queued: T should carry cumulative counters for anything
// that must not be lost.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace sinew::hal {

template <typename T>
class TripleBuffer {
 public:
  // Every copy starts as `prototype` (size containers here: the copies are
  // then reused in place, so publishing never allocates).
  explicit TripleBuffer(const T& prototype) : slots_{prototype, prototype, prototype} {}
  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  // Producer side. back() holds whatever was published two swaps ago:
  // overwrite all of it before publish().
  T& back() { return slots_[back_]; }
  void publish() {
    const uint8_t previous = middle_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = static_cast<uint8_t>(previous & kIndexMask);
  }

  // Consumer side. Takes the latest published value if there is a new one;
  // returns whether it did. front() stays valid and unchanged until then.
  bool refresh() {
    if ((middle_.load(std::memory_order_acquire) & kFresh) == 0) return false;
    const uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = static_cast<uint8_t>(previous & kIndexMask);
    return true;
  }
  const T& front() const { return slots_[front_]; }

 private:
  static constexpr uint8_t kIndexMask = 0x3;
  static constexpr uint8_t kFresh = 0x4;

  std::array<T, 3> slots_;
  alignas(64) uint8_t back_ = 0;   // producer only
  alignas(64) uint8_t front_ = 1;  // consumer only
  alignas(64) std::atomic<uint8_t> middle_{2};
  static_assert(std::atomic<uint8_t>::is_always_lock_free);
};

}  // namespace sinew::hal
