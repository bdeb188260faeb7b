// The viewer's overlay of the barnet stage: the bar-nets' free nodes.
#pragma once

#include "host_tools/view/overlays/overlay.hpp"

namespace sinew::view {

template <>
struct ViewOverlay<pipeline::Stage::kBarnet> {
  static void add(const pipeline::Pipeline& p, int32_t length_exponent, OverlayArrays* a, JsonText& j);
};

}  // namespace sinew::view
