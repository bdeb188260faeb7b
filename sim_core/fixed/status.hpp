// The one status type of sim_core's jobs (loaders, validators, init and step
// of every layer, the pipeline): an error code of the job's own enumeration
// (kNone on success) and a NUL-terminated message naming the record, field
// and value at fault, built without heap or stdio (rig/message.hpp).
#pragma once

#include <cstddef>

namespace sinew::fx {

inline constexpr size_t kStatusMessageBytes = 192;

template <typename Code>
struct Status {
  Code error = Code::kNone;
  char message[kStatusMessageBytes] = {};
  bool ok() const { return error == Code::kNone; }
};

}  // namespace sinew::fx
