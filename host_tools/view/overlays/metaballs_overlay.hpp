// The viewer's overlay of the metaballs stage: the metaballs: centre and radius.
#pragma once

#include "host_tools/view/overlays/overlay.hpp"

namespace sinew::view {

template <>
struct ViewOverlay<pipeline::Stage::kMetaballs> {
  static void add(const pipeline::Pipeline& p, int32_t length_exponent, OverlayArrays* a, JsonText& j);
};

}  // namespace sinew::view
