// The ring loads of a joint's net, scheduled over the joint's flexion so that
// the net's control tube keeps its rest volume. barnet-driven-skinning's
// Figure 2 binds "the gradually changed forces on the control mesh ... to
// the elbow rotation angle" to "compensate for the volume loss that the
// traditional smooth skinning method suffers", and leaves the forces to the
// animator; this derives them instead, from incompressible tissue.
//
// At `steps` angles evenly spread over the flexion, eq. (4) is solved in
// double for the net as the runtime forms it (the fixed nodes smoothly
// skinned, each free node's rest load turned by its blended bones at its
// bind-pose magnitude, barnet_model.hpp) with the ring's push scaled by f,
// and f is found by bisection so that the tube, closed by a fan at each end
// ring, encloses its rest volume. The schedule is then piecewise linear in
// the angle: one load per ring node and step, active from the step's first
// angle to its last, adding that step's change of f.
//
// Only + - * / and std::sqrt (the angles' sines and cosines from their
// Taylor series), so the schedule is bit-identical on every platform.
#pragma once

#include <string>
#include <vector>

#include "net_spec.hpp"

namespace sinew::layers::barnet {

struct RingLoadSchedule {
  int rings = 0, segments = 0;  // the tube, numbered as add_tube_mesh numbers it
  std::vector<uint32_t> nodes;  // the loaded ring's nodes (free)
  std::vector<Vec3d> push;      // per node: the load at f = 1 (bind frame, q x model units; about q x the radius)
  int carrier = 0;              // joint whose skinning matrix carries the loads
  int input = 0;                // rig input of the flexion DOF
  int joint = 0;                // the flexing joint: it and its descendants turn
  Vec3d centre{0, 0, 0};        // ... about `axis` (unit, model frame) through `centre`
  Vec3d axis{0, 0, 1};
  double flex_hi = 0;  // degrees, the flexion's end (its sign the turn's)
  int steps = 10;      // 1..64 samples over (0, flex_hi]
};

// The schedule: f at each step's angle (degrees), f = 0 at 0 degrees.
// f is searched within [-8, 8] (the push scaled to the tube's radius, f is
// of the order of 1); a step where no f there restores the volume (a bend
// that folds the tube onto itself) keeps the previous step's f and is
// counted.
struct VolumeSchedule {
  std::vector<double> angle, f;
  int short_steps = 0;
};

// Derives the schedule for `net` (its nodes, bars and triangles set); fails
// with a message on a schedule that does not fit the net.
bool volume_keeping_schedule(const rigc::RigSpec& rig, const RingLoadSchedule& schedule, const NetSpec& net,
                             VolumeSchedule* out, std::string* error);

// Derives the schedule and appends its loads to `net`.
bool add_volume_keeping_loads(const rigc::RigSpec& rig, const RingLoadSchedule& schedule, NetSpec* net,
                              std::string* error);

}  // namespace sinew::layers::barnet
