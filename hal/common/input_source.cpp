#include "input_source.hpp"

namespace sinew::hal {

const char* source_state_name(SourceState s) {
  switch (s) {
    case SourceState::kOk:
      return "ok";
    case SourceState::kDegraded:
      return "degraded";
    case SourceState::kDown:
      return "down";
  }
  return "unknown";
}

}  // namespace sinew::hal
