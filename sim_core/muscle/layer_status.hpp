// Result of a validator or step job of the anatomy layers (muscles, elastic
// skin): an error code and a message naming the offending record and field.
// Fixed-capacity text, built without heap or stdio.
#pragma once

#include <cstdint>

#include "sim_core/fixed/status.hpp"
#include "sim_core/rig/message.hpp"

namespace sinew::muscle {

enum class LayerError : uint8_t {
  kNone = 0,
  kBadModel,  // a model record is out of its documented range
  kBadInput,  // a step input (span size, bone transform count) disagrees with the model
  kMemory,    // caller memory missing, misaligned or too small
};

using LayerStatus = fx::Status<LayerError>;

// "<what>[index].<field>: <problem> (value)"; value shown when show_value.
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

}  // namespace sinew::muscle
