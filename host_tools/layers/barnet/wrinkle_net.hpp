// A wrinkle bar-net on the fine mesh (barnet-driven-skinning, Figure 6: "the
// bar-net is bound to the fine mesh rather than the rough mesh in order to
// obtain a detailed look"): its nodes are the built-in arm's skin vertices
// of a patch on the inner side of the elbow (the side that compresses when
// the elbow flexes), its bars the skin's edges there and the control
// triangles the skin's own triangles. The patch's border vertices are fixed
// (smoothly skinned), the inner ones free. Loads normal to the skin,
// alternating in sign from one skin ring to the next and growing with
// flexion, fold the compressed skin into creases across the arm; they are
// carried by the upper arm, on whose side of the elbow's crease the patch
// lies (its skin turns at most half the flexion there). Every free node wraps its own vertex (barycentric
// (1, 0, 0) to the rounding of the rest to Len, offset 0): the fine skin is
// the net.
#pragma once

#include "net_spec.hpp"

namespace sinew::layers::barnet {

struct WrinkleNetOptions {
  double x_lo = 0.25, x_hi = 0.31;     // m along the arm: the patch's first and last skin ring (fixed)
  int half_width = 4;                  // skin directions on each side of the inner line (+y); the outermost fixed
  double q = 1.0;                      // uniform force density
  double force = 0.004;                // q x m per free node at full flexion, along the skin's normal
  double flex_lo = 30, flex_hi = 150;  // degrees of elbow flexion: activation 0 -> 1
};

// Fails (with a message) if `arm` is not the built-in arm's layout or the
// patch leaves its skin.
bool arm_wrinkle_net(const rigc::RigSpec& arm, const WrinkleNetOptions& options, NetSpec* out, std::string* error);

}  // namespace sinew::layers::barnet
