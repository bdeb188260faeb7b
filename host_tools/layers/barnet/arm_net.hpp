// The built-in arm's elbow bar-net (barnet-driven-skinning, Figure 2): a
// coarse control tube around the elbow subsampled from the arm's skin
// (rings every 3 cm, 8 nodes each), the rings away from the elbow fixed and
// skinned, the rings around it free (eq. (4): the fixed rings pull them), and
// radial loads on the 8 nodes of one ring that follow elbow flexion to keep
// the tube's volume where the bend stretches it. The fine skin between the first
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
  int loaded_ring = 3;  // its 8 nodes are loaded
  double q = 1.0;       // uniform force density
  // The ring's radial push. 0 (the default): scheduled over the flexion so
  // that the control tube keeps its rest volume (volume_loads.hpp). > 0: a
  // push of this size at full flexion, q x m, growing linearly (the paper's
  // user handle). The net is eq. (4)'s equilibrium between the fixed rings,
  // so without a push its bars pull straight across the bend's outer side.
  double force = 0;
  double outer_share = 1.0;           // the outer side's share of the push (cosine profile between)
  double flex_lo = 0, flex_hi = 150;  // degrees of elbow flexion: activation 0 -> 1
  // Every bar's q follows external input 0 (the net then reads one external
  // input and re-factorises D every step).
  bool q_input = false;
  // Free nodes in reverse Cuthill-McKee order (NetSpec::profile_order; false:
  // the spec's order).
  bool profile_order = true;
};

// Fails (with a message) if `arm` is not the built-in arm's layout.
bool arm_elbow_net(const rigc::RigSpec& arm, const ArmNetOptions& options, NetSpec* out, std::string* error);

}  // namespace sinew::layers::barnet
