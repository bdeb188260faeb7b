// Builds a LayerStatus with a message naming the offending record and field.
#pragma once

#include "barnet_model.hpp"
#include "sim_core/rig/message.hpp"

namespace sinew::barnet {

// fail(&s, kBadIndex, "bars", 3, "b", "is not a node") ->
// "bars[3].b: is not a node"
inline LayerStatus fail(LayerError error, const char* array, uint64_t index, const char* field, const char* what) {
  LayerStatus s;
  s.error = error;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text(array).text("[").unsigned_number(index).text("].").text(field).text(": ").text(what);
  return s;
}

inline LayerStatus fail(LayerError error, const char* what) {
  LayerStatus s;
  s.error = error;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text(what);
  return s;
}

}  // namespace sinew::barnet
