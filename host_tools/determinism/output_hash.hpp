// Streaming xxHash64 of engine outputs, and the `determinism-hash` line printer.
#pragma once

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>

namespace sinew::determinism {

class OutputHash {
 public:
  OutputHash() { XXH64_reset(&state_, 0); }

  // Hashes values as little-endian bytes, so the digest does not depend on the
  // host's byte order.
  void add_i32(int32_t v) {
    const uint32_t u = static_cast<uint32_t>(v);
    const unsigned char b[4] = {static_cast<unsigned char>(u), static_cast<unsigned char>(u >> 8),
                                static_cast<unsigned char>(u >> 16), static_cast<unsigned char>(u >> 24)};
    XXH64_update(&state_, b, 4);
  }
  void add_u32(uint32_t v) { add_i32(static_cast<int32_t>(v)); }
  void add_i64(int64_t v) {
    add_u32(static_cast<uint32_t>(static_cast<uint64_t>(v)));
    add_u32(static_cast<uint32_t>(static_cast<uint64_t>(v) >> 32));
  }
  uint64_t digest() const { return XXH64_digest(&state_); }

 private:
  XXH64_state_t state_;  // on the stack: no allocation while hashing
};

// One line per workload, so builds can be compared from the outside.
inline void print_determinism_line(const char* workload, uint64_t digest) {
  std::printf("determinism-hash %s %016" PRIx64 "\n", workload, digest);
  std::fflush(stdout);
}

}  // namespace sinew::determinism
