#include "metaballs_overlay.hpp"

namespace sinew::view {

// Each ball's centre and radius (r0 x the volume-preserving scale).
void ViewOverlay<pipeline::Stage::kMetaballs>::add(const pipeline::Pipeline& p, int32_t e, OverlayArrays* a,
                                                   JsonText&) {
  const size_t balls = p.metaballs.on ? p.metaballs.state.ball_center.size() : 0;
  a->add("metaballs", 4 * balls);
  for (size_t b = 0; b < balls; ++b) {
    const fx::Vec3& c = p.metaballs.state.ball_center[b];
    a->push(metres(c.x, e));
    a->push(metres(c.y, e));
    a->push(metres(c.z, e));
    const double scale = std::ldexp(static_cast<double>(p.metaballs.state.ball_scale[b]), -30);
    a->push(metres(p.metaballs.state.model->ball_radius[b], e) * scale);
  }
}

}  // namespace sinew::view
