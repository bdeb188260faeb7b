// Long runs (soaks, large sweeps, fuzz campaigns) are opt-in: CI runs each
// test's short form; `scripts/soak.sh` sets SINEW_SOAK=1 and runs the long one.
//   const int steps = sinew::test::soak_enabled() ? 100000 : 5000;
#pragma once

#include <cstdlib>

namespace sinew::test {

inline bool soak_enabled() {
  const char* value = std::getenv("SINEW_SOAK");
  return value != nullptr && value[0] != '\0' && value[0] != '0';
}

// True in the cross builds, whose tests run under qemu-user (10-30x slower):
// a test whose native short form is already long may run fewer steps there.
inline constexpr bool emulated() {
#ifdef SINEW_TEST_EMULATED
  return true;
#else
  return false;
#endif
}

}  // namespace sinew::test
