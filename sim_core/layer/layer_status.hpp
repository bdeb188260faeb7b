// The one status of every physical layer's jobs (validate, state_bytes's
// companion init, step): a code from one enumeration shared by all layers and
// a message naming the record, field and value at fault, built without heap
// or stdio (rig/message.hpp). One type lets the stage table hold every
// layer's functions with the same signature and lets a caller report any
// layer's failure the same way.
#pragma once

#include <cstdint>

#include "sim_core/fixed/status.hpp"
#include "sim_core/rig/message.hpp"

namespace sinew::layer {

enum class LayerError : uint8_t {
  kNone = 0,
  kBadCount,  // a count zero where one is needed, or beyond the layer's documented maximum
  kBadSize,   // a span's length disagrees with the model's counts
  kBadIndex,  // an index (joint, vertex, node, ball, ...) outside its range
  kBadValue,  // a parameter or record value outside its documented range
  kSingular,  // a system the layer solves has no unique solution (e.g. a free node with no path to a fixed one)
  kArena,     // state memory missing, misaligned or smaller than <layer>_state_bytes
  kBadInput,  // a step input or output (transforms, forces, spans) disagrees with the model
  kNotReady,  // a state used before its init succeeded
};

using LayerStatus = fx::Status<LayerError>;

constexpr const char* layer_error_name(LayerError e) {
  switch (e) {
    case LayerError::kNone:
      return "none";
    case LayerError::kBadCount:
      return "bad count";
    case LayerError::kBadSize:
      return "bad size";
    case LayerError::kBadIndex:
      return "bad index";
    case LayerError::kBadValue:
      return "bad value";
    case LayerError::kSingular:
      return "singular";
    case LayerError::kArena:
      return "arena";
    case LayerError::kBadInput:
      return "bad input";
    case LayerError::kNotReady:
      return "not ready";
  }
  return "unknown";
}

// "<what>[index].<field>: <problem> (value)": index shown when >= 0, the
// field when non-empty, the value when show_value.
inline LayerStatus layer_fail(LayerError e, const char* what, int64_t index, const char* field, const char* problem,
                              int64_t value = 0, bool show_value = false) {
  LayerStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text(what);
  if (index >= 0) m.text("[").number(index).text("]");
  if (field != nullptr && *field != '\0') m.text(".").text(field);
  m.text(": ").text(problem);
  if (show_value) m.text(" (").number(value).text(")");
  return s;
}

}  // namespace sinew::layer
