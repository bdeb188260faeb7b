// Error reporting of the metaballs jobs: a code plus a message naming the
// offending field (and index), filled without heap or stdio.
#pragma once

#include <cstdint>

#include "sim_core/fixed/status.hpp"

namespace sinew::metaballs {

enum class Error : uint8_t {
  kNone = 0,
  kSize,      // a span's length disagrees with the counts
  kLimit,     // a count beyond the documented maxima
  kIndex,     // an index out of range
  kValue,     // a value out of its documented range
  kArena,     // state memory missing, misaligned or too small
  kNotReady,  // state not initialised for this model
};

using Status = fx::Status<Error>;

const char* error_name(Error e);

}  // namespace sinew::metaballs
