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
//
// skin_wrinkle_net builds the same net on any rig's skin mesh around a
// joint: the patch is the skin on the fold side of the bend within a window
// along the bone and an angle about the fold side; the mesh's own vertices
// (welded where copies share a position, as at texture seams), edges and
// triangles are the nodes, bars and control triangles; the vertices with a
// triangle outside the patch are fixed. The crease loads follow a cosine
// along the bone, along each vertex's normal.
#pragma once

#include "host_tools/layers/common/rig_geometry.hpp"
#include "net_spec.hpp"

namespace sinew::layers::barnet {

struct WrinkleNetOptions {
  double x_lo = 0.25, x_hi = 0.31;     // m along the arm: the patch's first and last skin ring (fixed)
  int half_width = 4;                  // skin directions on each side of the inner line (+y); the outermost fixed
  double q = 1.0;                      // uniform force density
  double force = 0.004;                // q x m per free node at full flexion, along the skin's normal
  double flex_lo = 30, flex_hi = 150;  // degrees of elbow flexion: activation 0 -> 1
};

struct SkinWrinkleOptions {
  // The patch's window: model units along the bone on each side of the
  // joint (0: the larger of 0.6 x skin radius and 2.5 x the skin's median
  // edge there) and degrees about the fold side (0: the larger of 60 and
  // the angle of 2.5 median edges at the skin radius, at most 180).
  double half_length = 0;
  double half_angle = 0;
  double q = 1.0;              // uniform force density
  double force = 0;            // q x model units per free node at full flexion; 0: 0.4 x the median edge
  double wavelength = 0;       // model units from crease to crease along the bone; 0: 2 x the median edge
  double flex_lo_share = 0.2;  // activation starts at this share of the flexion range (the arm's 30 of 150 deg)
};

// Fails, naming the joint, where joint_bend does, on options out of range,
// or when the patch holds no vertex whose triangles all lie in it.
bool skin_wrinkle_net(const rigc::RigSpec& rig, const RigGeometry& geometry, int joint,
                      const SkinWrinkleOptions& options, NetSpec* out, std::string* error);

// Fails (with a message) if `arm` is not the built-in arm's layout or the
// patch leaves its skin.
bool arm_wrinkle_net(const rigc::RigSpec& arm, const WrinkleNetOptions& options, NetSpec* out, std::string* error);

}  // namespace sinew::layers::barnet
