// The biceps/triceps bar-net of barnet-driven-skinning, Figure 3, on the
// built-in arm: a coarse control tube around the upper arm (rings every
// 3 cm, 8 nodes each) whose nodes all ride the upper arm. "Only the nodes
// lying around the central line of the two muscles are set to free, all
// other nodes are fixed": the node on the biceps' central line (the inner
// side, +y, towards which the forearm folds) and the one on the triceps'
// (-y) of each of the 6 inner rings are free, 12 free nodes as in the
// paper. "All the bars in the network are initially assigned a uniform
// force density." Loads on the midpoints of the two lines (Figure 3 (b)) grow
// with elbow flexion: the biceps' push outwards (it contracts and bulges),
// the triceps' inwards (it relaxes and is stretched flat). Lowering q
// enlarges the bulge (Figure 3 (d)). The fine skin of the upper arm between
// the end rings follows through the wrap binding.
//
// joint_muscle_net builds the same net on any rig: a control tube along the
// bone before `joint` (its anatomical parent's), on the skin there, the
// flexor line on the side the distal bone folds towards as the joint flexes,
// the extensor line opposite.
#pragma once

#include "host_tools/layers/common/rig_geometry.hpp"
#include "net_spec.hpp"

namespace sinew::layers::barnet {

struct MuscleNetOptions {
  double x0 = 0.025;                  // first ring (m along the arm); the last is x0 + 7 x ring_step
  double ring_step = 0.03;            // m; a multiple of the skin's 5 mm ring step
  double q = 1.0;                     // uniform force density
  double biceps_force = 0.02;         // q x m per loaded biceps node at full flexion, outwards
  double triceps_share = 0.5;         // the triceps' inward load, as a share of the biceps'
  double flex_lo = 0, flex_hi = 150;  // degrees of elbow flexion: activation 0 -> 1
};

inline constexpr int kMuscleNetRings = 8;     // 6 inner rings between 2 fixed end rings
inline constexpr int kMuscleNetSegments = 8;  // nodes per ring
inline constexpr int kMuscleNetFreeNodes = 12;

struct JointMuscleNetOptions {
  int rings = 8;                        // 5..15: 2 fixed end rings, the inner ones carry the two lines
  int segments = 8;                     // even, 4..32; k = 0 is the flexor line, k = segments / 2 the extensor
  double span_lo = 0.1, span_hi = 0.8;  // first and last ring, as shares of the bone from the parent's joint
  double q = 1.0;                       // uniform force density
  double force = 0;                     // q x model units per loaded flexor node at full flexion; 0: 0.4 x skin radius
  double extensor_share = 0.5;          // the extensor's inward load, as a share of the flexor's
};

// Fails, naming the joint, where joint_bend does, on options out of range,
// or on skin too sparse to place every node.
bool joint_muscle_net(const rigc::RigSpec& rig, const RigGeometry& geometry, int joint,
                      const JointMuscleNetOptions& options, NetSpec* out, std::string* error);

// Spec node index of the free node on a line of joint_muscle_net's tube:
// flexor (k = 0) or extensor (k = segments / 2) in ring `ring`.
uint32_t joint_muscle_line_node(const JointMuscleNetOptions& options, bool flexor, int ring);

// Spec node index of the free node on a muscle's central line in ring
// `ring` (1..6): biceps (inner side, +y) or triceps (-y).
uint32_t muscle_line_node(bool biceps, int ring);

// Fails (with a message) if `arm` is not the built-in arm's layout or the
// options place a ring outside the upper arm's skin.
bool arm_muscle_net(const rigc::RigSpec& arm, const MuscleNetOptions& options, NetSpec* out, std::string* error);

}  // namespace sinew::layers::barnet
