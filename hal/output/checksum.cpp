#include "checksum.hpp"

#define XXH_STATIC_LINKING_ONLY  // XXH64_state_t is complete: it lives on the stack
#include <xxhash.h>

namespace sinew::hal::output {

uint64_t xxh64(std::span<const uint8_t> bytes) { return XXH64(bytes.data(), bytes.size(), 0); }

uint64_t xxh64_concat(std::span<const uint8_t> first, std::span<const uint8_t> second) {
  XXH64_state_t state;  // on the stack: the per-tick paths never allocate
  XXH64_reset(&state, 0);
  XXH64_update(&state, first.data(), first.size());
  XXH64_update(&state, second.data(), second.size());
  return XXH64_digest(&state);
}

}  // namespace sinew::hal::output
