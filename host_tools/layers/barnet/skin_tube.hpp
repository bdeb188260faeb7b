// Skin sampling around a bone axis, shared by the bar-net builders that place
// a coarse control tube on any rig's skin (joint_net, joint_muscle_net) and
// pick a patch of the fine mesh around a joint (skin_wrinkle_net). Model
// units, double precision with + - * / and sqrt only.
#pragma once

#include <cstdint>
#include <set>
#include <vector>

#include "host_tools/layers/common/rig_geometry.hpp"

namespace sinew::layers::barnet {

// The bend at `joint`: the axis from its anatomical parent's joint to it,
// the mean skin radius of the two bones, and the side the distal bone folds
// towards as its first DOF turns to the end of its range (a positive turn
// about the DOF axis a moves the distal bone towards a x u).
struct Bend {
  int parent = -1;
  Vec3d c{0, 0, 0};      // the joint's rest position
  Vec3d u{1, 0, 0};      // unit, parent's joint -> joint
  double length = 0;     // parent's joint -> joint
  double radius = 0;     // mean skin radius of the parent's bone and the joint's
  Vec3d axis{0, 0, 1};   // unit, the first DOF's axis a in the model frame
  Vec3d inner{0, 1, 0};  // unit, a x u: the side a positive turn folds towards
  Vec3d fold{0, 1, 0};   // unit: the side full flexion folds towards (inner, or -inner)
  double flex_hi = 0;    // degrees: the end of the first DOF's range flexion runs to
  int input = 0;         // the rig input of that DOF
};

// Fails, naming the joint, on a root, a joint without a rotational DOF or
// with no range, or no skin on either bone.
bool joint_bend(const rigc::RigSpec& rig, const RigGeometry& g, int joint, Bend* out, std::string* error);

// A skin vertex seen from an axis through c along unit u.
struct SkinSample {
  uint32_t vertex;
  double axial;     // along u from c
  Vec3d radial;     // unit, perpendicular to u
  double distance;  // from the axis
};

// The bones whose skin lies around `joint`: its anatomical parent, itself and
// its children (a short bone's skin may belong to the next one; in a flat
// skeleton, the joints whose anatomical parent it is).
std::set<int> bones_around(const rigc::RigSpec& rig, const RigGeometry& g, int joint, int parent);

// The vertices dominated by `bones` within max_distance of the axis (and off
// it) and with axial in [axial_lo, axial_hi], bone by bone in increasing
// vertex order.
std::vector<SkinSample> skin_samples(const rigc::RigSpec& rig, const RigGeometry& g, const std::set<int>& bones,
                                     const Vec3d& c, const Vec3d& u, double max_distance, double axial_lo,
                                     double axial_hi);

// The skin's distance from the axis at height t in unit direction dir: the
// mean distance of the 4 samples nearest in height (in units of step) and in
// angle, so even a coarse mesh gives a tube. *nearest: the nearest one.
double skin_distance(const std::vector<SkinSample>& samples, double t, const Vec3d& dir, double step, size_t* nearest);

// A node of a control tube on the skin: on the ray from the axis point
// centre + t u at angle 2 pi k / segments in the plane of unit a and b, at
// the skin's distance there. `vertex`: the nearest skin vertex, whose skin
// weights the node takes (the control mesh is bound to the skeleton as the
// skin is).
struct TubePoint {
  Vec3d rest;
  uint32_t vertex;
};
TubePoint skin_tube_point(const std::vector<SkinSample>& samples, const Vec3d& centre, const Vec3d& u, const Vec3d& a,
                          const Vec3d& b, double t, int k, int segments, double step);

}  // namespace sinew::layers::barnet
