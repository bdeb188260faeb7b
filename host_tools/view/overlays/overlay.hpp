// What the viewer draws of each stage over the skin: ViewOverlay<Stage>,
// specialised in overlays/<stage>_overlay.hpp, appends the stage's arrays
// (named, float32, metres) and its JSON fields to a frame message;
// frame_message.cpp runs every stage's in the order of sim_core's stage list.
// The page (web/viewer.js) finds the arrays by name.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/view/json_text.hpp"
#include "sim_core/pipeline/pipeline.hpp"

namespace sinew::view {

// The float32 arrays of a frame message: each name with its length, the
// values one after another.
struct OverlayArrays {
  std::vector<std::pair<std::string, size_t>> names;
  std::vector<float> values;

  void add(const char* name, size_t count) { names.emplace_back(name, count); }
  void push(double v) { values.push_back(static_cast<float>(v)); }
};

// A rig length (Q12.20 in rig units of 2^length_exponent m) in metres.
inline double metres(int32_t q12_20, int32_t length_exponent) {
  return std::ldexp(static_cast<double>(q12_20), length_exponent - 20);
}

template <pipeline::Stage S>
struct ViewOverlay;

}  // namespace sinew::view
