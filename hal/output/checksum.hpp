// Checksums of the output formats: xxHash64 (seed 0) from the xxHash library.
// Kept behind this interface so no format header pulls in xxhash.h.
#pragma once

#include <cstdint>
#include <span>

namespace sinew::hal::output {

// XXH64(seed 0) of `bytes`.
uint64_t xxh64(std::span<const uint8_t> bytes);

// XXH64(seed 0) of `first` followed by `second`, as if they were contiguous:
// lets a header field and a payload that live apart be checked together.
uint64_t xxh64_concat(std::span<const uint8_t> first, std::span<const uint8_t> second);

}  // namespace sinew::hal::output
