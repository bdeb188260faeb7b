// Streaming xxHash64 of engine outputs, and the `determinism-hash` line printer.
#pragma once

#define XXH_STATIC_LINKING_ONLY  // XXH64_state_t is complete: it lives on the stack
#include <xxhash.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>

namespace sinew::determinism {

class OutputHash {
 public:
  OutputHash() { XXH64_reset(&state_, 0); }

  // Values are hashed as little-endian bytes, so the digest does not depend
  // on the host's byte order. They are staged in a block buffer (fewer
  // XXH64_update calls, and no tiny-array reads for gcc to misjudge).
  void add_u32(uint32_t u) {
    if (used_ + 4 > sizeof(block_)) flush();
    block_[used_++] = static_cast<unsigned char>(u);
    block_[used_++] = static_cast<unsigned char>(u >> 8);
    block_[used_++] = static_cast<unsigned char>(u >> 16);
    block_[used_++] = static_cast<unsigned char>(u >> 24);
  }
  void add_i32(int32_t v) { add_u32(static_cast<uint32_t>(v)); }
  void add_i64(int64_t v) {
    add_u32(static_cast<uint32_t>(static_cast<uint64_t>(v)));
    add_u32(static_cast<uint32_t>(static_cast<uint64_t>(v) >> 32));
  }
  uint64_t digest() {
    flush();
    return XXH64_digest(&state_);
  }

 private:
  void flush() {
    if (used_ > 0) XXH64_update(&state_, block_, used_);
    used_ = 0;
  }
  XXH64_state_t state_;  // on the stack: no allocation while hashing
  unsigned char block_[256];
  size_t used_ = 0;
};

// One line per workload, so builds can be compared from the outside.
inline void print_determinism_line(const char* workload, uint64_t digest) {
  std::printf("determinism-hash %s %016" PRIx64 "\n", workload, digest);
  std::fflush(stdout);
}

}  // namespace sinew::determinism
