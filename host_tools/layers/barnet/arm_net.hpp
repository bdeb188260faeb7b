// The built-in arm's elbow bar-net (barnet-driven-skinning, Figure 2): a
// coarse control tube around the elbow subsampled from the arm's skin
// (rings every 3 cm, 8 nodes each), the rings away from the elbow fixed and
// skinned, the rings around it free (eq. (4): the fixed rings pull them), and
// radial loads on the 8 nodes of one ring that grow with elbow flexion to
// hold the tube out where the bend stretches it. The fine skin between the first
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
  // The ring's radial push at full flexion, q x m. The net is eq. (4)'s
  // equilibrium between the fixed rings, so on the bend's outer side its
  // bars pull straight across the corner; this load holds the tube out.
  // 0.1 with a uniform share keeps the elbow segment's volume within 9 % of
  // rest up to 150 degrees, where smooth skinning loses 15 %
  // (tests/sim_core/barnet/barnet_arm_test.cpp prints both).
  double force = 0.1;
  double outer_share = 1.0;           // the outer side's share of the force (cosine profile between)
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
