// The rig the viewer draws: loaded as the daemon loads it (a blob file or a
// built-in name), with what the page needs once per connection: the
// triangles, the skeleton's parents, the input names and their units.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "firmware/rig/loaded_rig.hpp"

namespace sinew::view {

// How an input's i32 value reads (docs/frame-formats.md, pose payload).
enum class InputUnit : uint8_t {
  kDegrees,  // binary angle: 2^32 = one turn
  kMetres,   // Q12.20 rig units, one rig unit = 2^length_exponent metres
  kNewtons,  // Q16.16 newtons (an external force input)
  kRaw,      // another external input: Q16.16 in its declared unit
};

struct ViewRig {
  std::string name;  // as given on the command line
  firmware::LoadedRig loaded;
  std::vector<InputUnit> input_unit;  // one per input (the rig's, then external ones)
};

// `name_or_path`: an existing file is read as a blob; otherwise "arm", "hand"
// or "builtin:<name>" selects a built-in rig. false with *error set when
// neither loads.
bool load_view_rig(const std::string& name_or_path, ViewRig* out, std::string* error);

// An input's value in its unit (degrees, metres or newtons) for display.
double input_display_value(const ViewRig& rig, uint32_t input, int32_t value);

// The JSON message a page receives first: {"type":"rig", ...} with the
// triangles, joint parents and names, input names and units, and the layers.
std::string rig_message_json(const ViewRig& rig, uint32_t tick_hz);

}  // namespace sinew::view
