// When to try reopening a failed source: first after `initial_ns`, then with
// the delay doubling up to `max_ns`; a success resets the delay. Driven by the
// caller's clock so the simulated twin and tests are deterministic.
#pragma once

#include <cstdint>

namespace sinew::hal::can {

struct BackoffPolicy {
  uint64_t initial_ns = 100'000'000;  // 100 ms
  uint64_t max_ns = 5'000'000'000;    // 5 s
};

class ReopenBackoff {
 public:
  explicit ReopenBackoff(BackoffPolicy policy = {}) : policy_(policy), delay_ns_(policy.initial_ns) {}

  // The source failed at now_ns (or an attempt failed): schedule the next try.
  void failed(uint64_t now_ns);
  void succeeded() { delay_ns_ = policy_.initial_ns; }
  bool due(uint64_t now_ns) const { return now_ns >= next_attempt_ns_; }
  uint64_t next_attempt_ns() const { return next_attempt_ns_; }

 private:
  BackoffPolicy policy_;
  uint64_t delay_ns_;
  uint64_t next_attempt_ns_ = 0;
};

}  // namespace sinew::hal::can
