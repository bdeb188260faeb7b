// Deterministic input generator (SplitMix64): same sequence on every platform.
#pragma once

#include <cstdint>

namespace sinew::determinism {

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
  }
  uint32_t next_u32() { return static_cast<uint32_t>(next() >> 32); }
  int32_t next_i32() { return static_cast<int32_t>(next_u32()); }
  // Uniform in [lo, hi] for hi - lo < 2^32.
  int32_t range(int32_t lo, int32_t hi) {
    const uint64_t span = static_cast<uint64_t>(int64_t{hi} - lo) + 1;
    return static_cast<int32_t>(lo + static_cast<int64_t>(next() % span));
  }

 private:
  uint64_t state_;
};

}  // namespace sinew::determinism
