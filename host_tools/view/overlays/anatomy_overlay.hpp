// The viewer's overlay of the anatomy stage: the muscles' surface vertices.
#pragma once

#include "host_tools/view/overlays/overlay.hpp"

namespace sinew::view {

template <>
struct ViewOverlay<pipeline::Stage::kAnatomy> {
  static void add(const pipeline::Pipeline& p, int32_t length_exponent, OverlayArrays* a, JsonText& j);
};

}  // namespace sinew::view
