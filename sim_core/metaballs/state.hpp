// Runtime state of the metaballs layer: scratch and the jiggle history, carved
// from caller memory at init (state_bytes tells how much); a step never
// allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "model.hpp"
#include "sim_core/fixed/dual_quat.hpp"
#include "status.hpp"

namespace sinew::metaballs {

// Stages a caller may switch off (tests compare with and without them).
struct Features {
  bool pbd = true;           // stretch constraints and jiggle springs
  bool jiggle = true;        // jiggle springs (off: jiggle balls follow their kinematic centre)
  bool action_lines = true;  // the model's action-line constraints (it has none by default)
  bool bulge = true;
  bool joint_balls = true;  // eq. (5) and the blend of eq. (1)
  bool smoothing = true;
  bool overlap = true;
  // The frames on the arc made once per (balls, weights) key and shared by
  // its vertices (off: one per vertex; the same words either way).
  bool shared_frames = true;
};

struct StepStats {
  uint64_t steps = 0;
  uint32_t projected_vertices = 0;  // overlap projections in the last step
  uint32_t skipped_pairs = 0;       // coincident ball pairs left alone in the last step
};

namespace detail {
// A vertex's frame from its normal balls: the blended centre
// sum_j w_j c_j (Len, rounded), the blended rest displacement
// sum_j w_j s_j d_ij (Len, saturated) and the rotation (kernels.hpp:
// vertex_rotation, or joint_region_frame's on the arc).
struct NormalBallFrame {
  int64_t centre[3];  // |.| < 2^31
  fx::Vec3 disp;
  fx::Quat quat;
  fx::Rot3 rotation;
};
}  // namespace detail

// No shared frame (MetaballState::vertex_frame).
inline constexpr uint32_t kNoFrame = 0xFFFFFFFFu;

struct MetaballState {
  const MetaballModel* model = nullptr;
  Features features;
  bool primed = false;  // jiggle history valid (false: the next step starts at
                        // rest velocity)
  StepStats stats;
  // Per bone: deformation T_j = model_j * inverse_bind_j and its rotation.
  std::span<fx::Mat34> bone;
  std::span<fx::Quat> bone_rotation;
  // Per normal ball.
  std::span<fx::Vec3> ball_center;    // after PBD, Len
  std::span<fx::Vec3> ball_previous;  // jiggle balls: centre one step earlier
  std::span<fx::Vec3> ball_target;    // kinematic centre of eq. (2), Len
  // Jiggle balls of a model with jiggle_rate_hz > 0: the kinematic centre one
  // step earlier and its last step.
  std::span<fx::Vec3> ball_last_target;
  std::span<fx::Vec3> ball_last_step;
  // ... and the swing carried below the Len step ([ball * 3 + axis], Len
  // with 24 more fraction bits): the fraction the centre did not take, and
  // the whole swing one step earlier.
  std::span<int64_t> swing_fraction;
  std::span<int64_t> swing_previous;
  // Per ball of a model with jiggle_rate_hz > 0 (empty otherwise): its
  // jiggle gains k and d at the rate the state runs at (tick_hz; init: the
  // model's gains and rate, set_tick_rate converts them).
  std::span<fx::Unit> jiggle_stiffness;
  std::span<fx::Unit> jiggle_damping;
  // Per stretch pair of a model with jiggle_rate_hz > 0 (empty otherwise):
  // its coupling x = (omega_c h)^2 at the state's rate (jiggle_gains.hpp,
  // coupling_for_rate); per ball, the springs' pull h^2 F of this tick
  // ([ball * 3 + axis], Len with 24 more fraction bits).
  std::span<fx::Unit> pair_coupling;
  std::span<int64_t> ball_pull;
  uint32_t tick_hz = 0;
  // Per action ball: its point of the line this step (the line is kinematic).
  std::span<fx::Vec3> action_point;
  std::span<fx::Rot3> ball_rotation;  // R^lambda
  std::span<fx::Quat> ball_quat;      // R^lambda as a unit quaternion (blended per vertex)
  // Each ball's frame x -> c + R (x - c0) as a dual quaternion, made once a
  // step for the vertices whose balls turn differently (deform.cpp).
  std::span<fx::DualQuat> ball_frame;
  bool ball_frames_near_unit = false;  // every real component within 2^30 + 2^28 of zero
  std::span<fx::Unit> ball_scale;      // r / r0 in [1, 2), Q2.30
  // Overlap between bones sharing no joint: 1 for a listed ball that collides
  // with a ball of the other bone this step (scratch of overlap.cpp).
  std::span<uint8_t> ball_touching;
  // Per vertex, made at init from the model alone (make_rest_blends,
  // kernels.hpp): the two blends of eq. (4) that read no pose, each
  // sat_i32(round_shift(sum, 30)) as the step rounds them. rest_centre:
  // sum_j w_j c0_j (the balls' rest centres); rest_disp: sum_j w_j d_ij, the
  // displacement blend wherever every weighted ball's scale is 1. Len.
  std::span<fx::Vec3> vertex_rest_centre;
  std::span<fx::Vec3> vertex_rest_disp;
  // The bone every weighted ball of the vertex follows alone (ball_bone,
  // kernels.hpp), or kNoBall.
  std::span<uint16_t> vertex_bone;
  // Shared frames (shared_frames.cpp), indexed at init from the model alone:
  // per vertex the key of its balls and weights, kNoFrame for a vertex that
  // turns with one bone (vertex_bone) outside eq. (1); per key its first
  // vertex and, each step, its frame on the arc (the disp of that vertex);
  // frame_table: the open-addressing table the index was built with.
  std::span<uint32_t> vertex_frame;
  std::span<uint32_t> frame_vertex;
  std::span<detail::NormalBallFrame> shared_frame;
  std::span<uint32_t> frame_table;
  uint32_t frame_count = 0;
  bool balls_scaled = false;  // a ball's scale is not 1 this step (make_shared_frames)
  // Per joint-region vertex.
  std::span<fx::Vec3> jv_posed_laplacian;  // rest Laplacian rotated with the vertex
  std::span<fx::Vec3> jv_scratch;          // Jacobi smoothing buffer
};

// Bytes of state memory init needs for a (validated) model.
size_t metaballs_state_bytes(const MetaballModel& model);

// Validates the model, carves `memory` (8-byte aligned, >= state_bytes) and
// sets the rest state. The model must outlive the state.
LayerStatus metaballs_init(const MetaballModel& model, void* memory, size_t bytes, MetaballState* out);

// Runs a model with physical jiggle (jiggle_rate_hz > 0) at tick_hz: every
// jiggle ball's gains are converted from the model's rate
// (jiggle_gains_for_rate), so the swing keeps its frequency and window, and
// every stretch pair's coupling (coupling_gains), so the springs keep theirs.
// A model without physical jiggle, or tick_hz equal to the model's rate,
// keeps the model's gains. kBadValue (state unchanged) if tick_hz is 0 or
// cannot carry the swing. Also forgets the jiggle history.
LayerStatus set_tick_rate(MetaballState* s, uint32_t tick_hz);

// Forgets the jiggle history: the next step starts from the kinematic pose.
inline void reset(MetaballState* s) { s->primed = false; }

}  // namespace sinew::metaballs
