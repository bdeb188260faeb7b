// A bar-net around any joint of any rig (barnet-driven-skinning, Figure 2):
// rings of control nodes picked from the skin around the bend between the
// joint's parent bone and its own, the end rings fixed and skinned, the
// middle ones free, radial loads on the ring at the joint that grow with the
// joint's flexion (heavier on the inner side of the bend) to restore the
// volume smooth skinning loses. The fine skin between the end rings follows
// the control mesh through a wrap binding. Every default derives from the
// rig's geometry (layers/common/rig_geometry.hpp): the skin radius R around
// the joint sets the ring spacing (0.65 R); the ring's push keeps the
// control tube's rest volume over the flexion (volume_loads.hpp).
#pragma once

#include "host_tools/layers/common/rig_geometry.hpp"
#include "net_spec.hpp"

namespace sinew::layers::barnet {

struct JointNetOptions {
  int segments = 8;      // nodes per ring, 3..32
  int rings = 7;         // odd, 5..15; the middle ring sits on the joint
  double ring_step = 0;  // model units between rings; 0: 0.65 x skin radius
  double q = 1.0;        // uniform force density
  // The ring's push. 0 with no force_input (the default): scheduled over the
  // flexion so that the control tube keeps its rest volume
  // (volume_loads.hpp). Otherwise q x model units at full activation,
  // growing linearly; 0 then means 2.2 x skin radius.
  double force = 0;
  double outer_share = 1.0;  // the outer side's share of the force (cosine profile between)
  // Inputs (EXTI indices into external_count inputs; -1: none).
  uint32_t external_count = 0;
  int force_input = -1;                            // activates the loads instead of the flexion
  double force_input_lo = 0, force_input_hi = 40;  // input values (its unit) for activation 0 and 1
  int q_input = -1;                                // scales every bar's q (dimensionless value)
};

// Fails, naming the joint and the problem, on a root joint, a joint without
// a rotational DOF, or skin too sparse to give every node its own vertex.
bool joint_net(const rigc::RigSpec& rig, const RigGeometry& geometry, int joint, const JointNetOptions& options,
               NetSpec* out, std::string* error);

}  // namespace sinew::layers::barnet
