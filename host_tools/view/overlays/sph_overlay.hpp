// The viewer's overlay of the sph stage: every SPH joint's particles, their pressure and yield, and each joint's yield.
#pragma once

#include "host_tools/view/overlays/overlay.hpp"

namespace sinew::view {

template <>
struct ViewOverlay<pipeline::Stage::kSph> {
  static void add(const pipeline::Pipeline& p, int32_t length_exponent, OverlayArrays* a, JsonText& j);
};

}  // namespace sinew::view
