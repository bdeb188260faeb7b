// The viewer's overlay of the skinning stage: the skeleton: model-space joint origins.
#pragma once

#include "host_tools/view/overlays/overlay.hpp"

namespace sinew::view {

template <>
struct ViewOverlay<pipeline::Stage::kSkinning> {
  static void add(const pipeline::Pipeline& p, int32_t length_exponent, OverlayArrays* a, JsonText& j);
};

}  // namespace sinew::view
