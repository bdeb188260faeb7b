// Exponential back-off: initial, 2x, 4x ... capped at max; reset on success.
// Keeps a dead device from being hammered while still noticing its return.
#pragma once

#include <cstdint>

namespace sinew::hal::modbus {

class Backoff {
 public:
  Backoff(uint64_t initial_ns, uint64_t max_ns) : initial_(initial_ns), max_(max_ns) {}
  // The wait before the next attempt; each call doubles the following one.
  uint64_t next() {
    const uint64_t wait = next_ == 0 ? initial_ : next_;
    next_ = wait >= max_ / 2 ? max_ : wait * 2;
    current_ = wait;
    return wait;
  }
  void reset() {
    next_ = 0;
    current_ = 0;
  }
  uint64_t current() const { return current_; }  // the last wait handed out; 0 after reset

 private:
  uint64_t initial_;
  uint64_t max_;
  uint64_t next_ = 0;
  uint64_t current_ = 0;
};

}  // namespace sinew::hal::modbus
