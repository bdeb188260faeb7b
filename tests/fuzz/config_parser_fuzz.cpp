// libFuzzer target: any bytes as a sinewd config file. The parser must
// accept it or reject it with a message; never crash or hang.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "firmware/daemon/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  sinew::firmware::DaemonConfig config;
  std::string error;
  if (!sinew::firmware::parse_config(text, "fuzz.toml", &config, &error) && error.empty()) __builtin_trap();
  return 0;
}
