// Step-time statistics without allocation: a fixed log-linear histogram
// (16 sub-buckets per power of two, 1 ns .. ~68 s) gives p50/p99 within
// 1/16 relative error; max and deadline misses are exact.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace sinew::firmware {

class StepTiming {
 public:
  void record(uint64_t step_ns, bool missed_deadline);
  uint64_t percentile_ns(double p) const;  // upper edge of the bucket holding p
  uint64_t max_ns() const { return max_; }
  uint64_t count() const { return count_; }
  uint64_t deadline_misses() const { return misses_; }
  void reset() { *this = StepTiming{}; }

 private:
  static constexpr int kSub = 16;
  static constexpr int kOctaves = 36;
  static size_t bucket_of(uint64_t ns);
  static uint64_t upper_edge(size_t bucket);
  std::array<uint64_t, kSub * kOctaves> buckets_{};
  uint64_t count_ = 0, max_ = 0, misses_ = 0;
};

}  // namespace sinew::firmware
