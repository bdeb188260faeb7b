// The metaballs skinning model (metaballs-pbd-skinning): immutable data built
// offline (host_tools/layers/metaballs) and read by the runtime step. Plain
// spans over caller-owned memory; nothing here allocates.
//
// Units and formats (docs/numerics.md):
//   positions, displacements, radii, rest lengths: Len, Q12.20 rig units
//   weights, stiffnesses, shares, gains, rates:    Unit, Q2.30, in [0, 1]
//   unless noted directions:                                    Unit, Q2.30,
//   unit length inverse binds:                                 Mat34 (Lin Q8.24
//   linear part, Len translation)
// "Bone j" is the segment driven by joint j; its deformation is
// T_j = model_j * inverse_bind_j (identity at the rest pose).
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/mat34.hpp"

namespace sinew::metaballs {

// Documented maxima; metaballs_validate() rejects larger models, which bounds a step's
// work.
inline constexpr uint32_t kMaxJoints = 1024;
inline constexpr uint32_t kMaxBalls = 4096;
inline constexpr uint32_t kMaxPairs = 8 * kMaxBalls;
inline constexpr uint32_t kMaxActionLines = 256;
inline constexpr uint32_t kMaxActionBalls = kMaxBalls;
inline constexpr uint32_t kMaxVertices = 1u << 20;
inline constexpr uint32_t kMaxJointBalls = kMaxJoints;
inline constexpr uint32_t kMaxNeighbours = 16;  // per joint-region vertex
inline constexpr uint32_t kMaxPbdIterations = 16;
inline constexpr uint32_t kMaxSmoothingPasses = 8;
inline constexpr uint32_t kMaxOverlapWork = 1u << 24;  // vertex-ball tests per step, summed
inline constexpr uint32_t kBallInfluences = 2;         // bones per normal ball (w^beta)
inline constexpr uint32_t kVertexBalls = 4;            // normal balls per vertex (w^gamma)
inline constexpr uint16_t kNoBall = 0xFFFF;
inline constexpr uint16_t kNoJoint = 0xFFFF;  // an overlap record of two bones sharing no joint
inline constexpr uint32_t kMaxOverlaps = 8 * kMaxJoints;
inline constexpr uint32_t kMaxOverlapBalls = 8 * kMaxBalls;

// A stretch constraint between two normal balls, eq. (3): C = |c_a - c_b| - d.
// share_a + share_b = 1 split the correction (0 pins a ball: a kinematic
// ball anchors a jiggle region); stiffness scales it per iteration.
struct BallPair {
  uint16_t a, b;
  fx::Len rest;  // d, > 0
  fx::Unit share_a;
  fx::Unit share_b;
  fx::Unit stiffness;
};

// Muscle bulging: the ball's radius, and the skin displacements over it, grow
// with the angle theta between bones a and b (relative to rest):
//   r = r0 * (1 + gain * (1 - cos theta) / 2),   gain in [0, 1), so r < 2 r0.
struct BulgeRecord {
  uint16_t ball;
  uint16_t bone_a, bone_b;
  uint16_t reserved;
  fx::Unit gain;
};

// An action line (the paper's simplified muscle or tendon, its ref. [5]):
// the segment from a point carried by bone `origin_bone` to one carried by
// `insertion_bone`, both given at rest in model space (Len). Posed, its ends
// are T_origin origin_rest and T_insertion insertion_rest.
struct ActionLine {
  uint16_t origin_bone, insertion_bone;
  uint32_t reserved;
  fx::Vec3 origin_rest, insertion_rest;
};

// A ball that follows an action line: a PBD constraint keeps it at its rest
// distance from the line's point at `along` (0 origin, 1 insertion):
//   C = |c - L(along)| - rest,  L(t) = O + t (I - O),
// projected with `stiffness` per iteration, the line kinematic (it moves only
// the ball). As the joint moves, the line's point moves and the ball with it.
struct ActionBall {
  uint16_t ball, line;
  fx::Unit along;      // [0, 1]
  fx::Len rest;        // >= 0
  fx::Unit stiffness;  // [0, 1]
};

// A joint ball, eq. (5): centred on the skeleton joint `joint`, which joins
// bone_a (parent side) and bone_b (child side); both carry it equally.
struct JointBall {
  uint16_t joint;
  uint16_t bone_a, bone_b;
  uint16_t reserved;
  fx::Vec3 rest_center;  // Len, the joint's rest position
  fx::Len radius;        // r^eta, outer radius of its region (informational)
};

// Surface overlapping at a joint: vertices of one bone's region found inside
// the other bone's balls, beyond the interior plane, are projected onto it.
// The plane passes through the joint with normal R_a dir_a - R_b dir_b
// (the bisector of the two bone directions; bone a's side is positive).
// Candidate lists are ranges of overlap_vertices / overlap_balls.
//
// Two bones that share no joint and can meet (fingers side by side, a
// fingertip and the palm): joint == kNoJoint, dir_a and dir_b zero. Each
// step the two ball lists detect their collision: a pair of balls (one of
// each list) that overlaps now but not at rest (where it is one tissue).
// A listed vertex of one bone inside a colliding ball of the other is then
// projected onto the interior plane between that ball and the vertex's own
// ball (its first of eq. (4)): normal from the other ball's centre to its
// own, through the middle of the two balls' overlap.
struct OverlapRecord {
  uint16_t joint, bone_a, bone_b, reserved;
  fx::Vec3 dir_a, dir_b;  // Unit, rest directions from the joint into each bone
  uint32_t vertices_a_begin, vertices_a_end, vertices_b_begin, vertices_b_end;
  uint32_t balls_a_begin, balls_a_end, balls_b_begin, balls_b_end;
};

struct MetaballModel {
  uint32_t joint_count = 0;  // of the skeleton whose transforms drive the step
  uint32_t vertex_count = 0;

  std::span<const fx::Mat34> inverse_bind;  // [joint]

  // Normal balls.
  std::span<const fx::Vec3> ball_rest;    // c^lambda, Len
  std::span<const fx::Len> ball_radius;   // r0 > 0
  std::span<const uint16_t> ball_bone;    // owning bone (its ball set)
  std::span<const uint16_t> ball_joint;   // [ball * kBallInfluences + k]
  std::span<const fx::Unit> ball_weight;  // w^beta, sums to 2^30 per ball
  std::span<const fx::Unit> ball_jiggle;  // spring stiffness in (0, 1], 0 = kinematic
  std::span<const BallPair> pairs;
  std::span<const BulgeRecord> bulges;
  std::span<const ActionLine> action_lines;  // none: no action lines (the default)
  std::span<const ActionBall> action_balls;  // projected after the pairs in every sweep
  uint32_t pbd_iterations = 0;               // stretch-projection sweeps per step
  fx::Unit jiggle_damping = 0;               // velocity kept per step, [0, 1)
  // 0: ball_jiggle and jiggle_damping are per-step gains of the ball's own
  // motion (a jiggle ball lags a moving bone). > 0: they are
  // metaballs::jiggle_gains for this tick rate (Hz): the swing is that of
  // flesh on the bone, the damping acts on the motion relative to the
  // kinematic centre and the bone's acceleration drives it, so the motion is
  // the continuous one of jiggle_gains.hpp at every tick.
  uint32_t jiggle_rate_hz = 0;

  // Deformation by normal balls, eq. (4): [vertex * kVertexBalls + k].
  std::span<const uint16_t> vertex_ball;
  std::span<const fx::Unit> vertex_weight;  // w^gamma, sums to 2^30 per vertex
  std::span<const fx::Vec3> vertex_disp;    // d^lambda = v - c^lambda, Len

  // Joint balls and their region: per joint-region vertex (ascending vertex
  // index).
  std::span<const JointBall> joint_balls;
  std::span<const uint32_t> jv_vertex;
  std::span<const uint16_t> jv_ball;             // index into joint_balls
  std::span<const fx::Unit> jv_alpha;            // w^alpha of eq. (1), (0, 1]
  std::span<const fx::Unit> jv_blend;            // rotation blend bone_a -> bone_b, [0, 1]
  std::span<const fx::Vec3> jv_disp;             // d^eta = v - c^eta, Len
  std::span<const fx::Vec3> jv_laplacian;        // rest mean(neighbours) - v, Len
  std::span<const uint32_t> jv_neighbour_begin;  // [jv_count + 1]
  std::span<const uint32_t> jv_neighbours;       // vertex indices
  std::span<const fx::Unit> jv_inv_count;        // 1 / neighbour count
  uint32_t smoothing_passes = 0;
  fx::Unit smoothing_rate = 0;

  std::span<const OverlapRecord> overlaps;
  std::span<const uint32_t> overlap_vertices;
  std::span<const uint16_t> overlap_balls;

  uint32_t ball_count() const { return static_cast<uint32_t>(ball_rest.size()); }
  uint32_t jv_count() const { return static_cast<uint32_t>(jv_vertex.size()); }
};

}  // namespace sinew::metaballs
