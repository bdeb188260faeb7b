#include "barnet_overlay.hpp"

namespace sinew::view {

// Each net's free nodes at their smooth-skinned positions.
void ViewOverlay<pipeline::Stage::kBarnet>::add(const pipeline::Pipeline& p, int32_t e, OverlayArrays* a, JsonText&) {
  size_t nodes = 0;
  for (uint32_t n = 0; n < p.barnet.count; ++n) nodes += p.barnet.net[n].skinned[0].size();
  a->add("barnet", 3 * nodes);
  for (uint32_t n = 0; n < p.barnet.count; ++n)
    for (size_t k = 0; k < p.barnet.net[n].skinned[0].size(); ++k)
      for (int c = 0; c < 3; ++c) a->push(metres(p.barnet.net[n].skinned[c][k], e));
}

}  // namespace sinew::view
