#include "anatomy_overlay.hpp"

namespace sinew::view {

// The muscles' surface vertices (rings of slices).
void ViewOverlay<pipeline::Stage::kAnatomy>::add(const pipeline::Pipeline& p, int32_t e, OverlayArrays* a, JsonText&) {
  const size_t muscle_vertices = p.anatomy.on ? p.anatomy.muscles.vertex[0].size() : 0;
  a->add("muscles", 3 * muscle_vertices);
  for (size_t v = 0; v < muscle_vertices; ++v)
    for (int c = 0; c < 3; ++c) a->push(metres(p.anatomy.muscles.vertex[c][v], e));
}

}  // namespace sinew::view
