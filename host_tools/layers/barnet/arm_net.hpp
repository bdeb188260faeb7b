// The built-in arm's elbow bar-net (barnet-driven-skinning, Figure 2): a
// coarse control tube around the elbow subsampled from the arm's skin
// (rings every 3 cm, 8 nodes each), the rings away from the elbow fixed and
// skinned, the rings around it free, and radial loads on the 8 nodes of one
// ring that grow with elbow flexion to restore the volume smooth skinning
// loses and raise a bulge on the inner side. The fine skin between the first
// and last ring follows the control mesh through a wrap binding.
#pragma once

#include "net_spec.hpp"

namespace sinew::layers::barnet {

struct ArmNetOptions {
  double x0 = 0.18;         // first ring (m, along the arm)
  double ring_step = 0.03;  // m; a multiple of the skin's 5 mm ring step
  int rings = 7;
  int segments = 8;  // divides the skin's 32
  int first_free_ring = 2, last_free_ring = 4;
  int loaded_ring = 3;                // its 8 nodes are loaded
  double q = 1.0;                     // uniform force density
  double force = 0.05;                // q x m at full flexion, on the inner side
  double outer_share = 0.5;           // the outer side's share of the force (cosine profile between)
  double flex_lo = 0, flex_hi = 150;  // degrees of elbow flexion: activation 0 -> 1
  // Every bar's q follows external input 0 (the net then reads one external
  // input and re-factorises D every step).
  bool q_input = false;
  // Free nodes in reverse Cuthill-McKee order (NetSpec::profile_order).
  bool profile_order = false;
};

// Fails (with a message) if `arm` is not the built-in arm's layout.
bool arm_elbow_net(const rigc::RigSpec& arm, const ArmNetOptions& options, NetSpec* out, std::string* error);

}  // namespace sinew::layers::barnet
