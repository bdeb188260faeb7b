// Internal stages of metaballs::step (one file each); sizes already checked.
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/layer/workers.hpp"
#include "sim_core/skin/skinning.hpp"
#include "state.hpp"

namespace sinew::metaballs::detail {

// balls.cpp: stages 1 and 2.
void compute_bones(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s);
void compute_balls(const MetaballModel& m, MetaballState* s);

// pbd.cpp: stage 3.
void solve_pbd(const MetaballModel& m, MetaballState* s);
// Whether physical jiggle's coupling springs (jiggle_gains.hpp) are stable
// with the swing at tick_hz (Gershgorin and Jury bounds; uses s->ball_pull
// as scratch). True for a model without them.
bool coupling_stable(const MetaballModel& m, MetaballState* s, uint32_t tick_hz);

// deform.cpp: stage 4, eq. (4) over every vertex by the chosen kernel, then
// the joint balls (eq. 5) blended by eq. (1). Every kernel writes the same
// words; the default is the fastest the CPU runs.
enum class DeformKernel : uint8_t { kScalar, kAvx2 };
bool deform_kernel_supported(DeformKernel kernel);
DeformKernel deform_kernel_default();
void deform_vertices(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s,
                     const skin::SkinnedVertices& out, DeformKernel kernel = deform_kernel_default(),
                     const layer::Workers* workers = nullptr);

// The rotation of a vertex's normal balls (deform.cpp): the shared ball's own
// when every weighted ball has the same one (returns that ball), else their
// nlerp by the vertex's weights, written to *quat and *rotation (returns
// kNoBall). The vertex has a weight.
uint16_t vertex_rotation(const MetaballModel& m, const MetaballState& s, uint32_t v, fx::Quat* quat,
                         fx::Rot3* rotation);

// A vertex's frame from its normal balls (NormalBallFrame, state.hpp).
NormalBallFrame normal_ball_frame(const MetaballModel& m, const MetaballState& s, uint32_t v);

// The state's vertex_rest_centre, vertex_rest_disp and vertex_bone from the model
// (init; again by whoever changes the model's weights, balls, displacements
// or rest centres under a state). The vector kernels read them instead of
// blending per step what no pose changes; the specification blends as it
// always did, so the kernel tests check these too.
void make_rest_blends(const MetaballModel& m, MetaballState* s);

// The bone a normal ball follows alone (its rotation is that bone's,
// compute_balls), or kNoBall for a ball of two bones.
uint16_t ball_bone(const MetaballModel& m, uint32_t b);
// True when every ball of one bone has its bone's rotation this step (as
// compute_balls makes it): a vertex whose weighted balls all follow one bone
// (vertex_bone) then turns alike without comparing their rotations.
bool one_bone_balls_follow_bones(const MetaballModel& m, const MetaballState& s);

// Each ball's frame x -> c + R (x - c0) as a dual quaternion (ball_frame),
// made once a step before the vertex loops, and whether every frame's real
// part lies near unit (ball_frames_near_unit; the vector kernel below needs
// it for its plain hemisphere dot).
void make_ball_frames(const MetaballModel& m, MetaballState* s);
// Near unit: |component| <= 2^30 + 2^28, so the plain dot of two real parts
// is below 4 (1.25 * 2^30)^2 < 2^63, exact in int64.
inline constexpr int64_t kFrameRealLimit = (int64_t{1} << 30) + (int64_t{1} << 28);

// Eq. (4) on the arc for a vertex whose balls turn differently: the
// dual-quaternion blend of its balls' frames by its weights, with the blended
// rest displacement sum_j w_j s_j d_ij (deform.cpp). The scalar
// specification.
NormalBallFrame joint_region_frame(const MetaballModel& m, const MetaballState& s, uint32_t v);

// joint_region_frame of vertices[i] into frames[i] (equal lengths), by the
// kernel chosen: every kernel writes the same words. The AVX2 kernel
// (joint_frame_avx2.cpp) blends four vertices at once and hands a vertex it
// cannot prove exact to the specification.
void joint_region_frames(const MetaballModel& m, const MetaballState& s, std::span<const uint32_t> vertices,
                         std::span<NormalBallFrame> frames, DeformKernel kernel);
#if defined(__x86_64__)
void joint_region_frames_avx2(const MetaballModel& m, const MetaballState& s, std::span<const uint32_t> vertices,
                              std::span<NormalBallFrame> frames);
#endif

// Shared frames (shared_frames.cpp): joint_region_frame reads a vertex's
// balls, weights and displacements, and vertices with the same balls and
// weights (a ring of a tube) differ only in the displacement blend. So the
// state keys the vertices that may need a frame on the arc by their slots at
// init, a step makes each key's frame once (make_shared_frames, after
// make_ball_frames), and shared_vertex_frame returns that frame with the
// vertex's own displacement blend: joint_region_frame's words.
// The bone every weighted ball of vertex v follows alone, or kNoBall
// (make_rest_blends' vertex_bone).
uint16_t vertex_one_bone(const MetaballModel& m, uint32_t v);
// How many vertices may need a frame (an upper bound of the keys), and the
// index table's size for them (a power of two, at least twice as many).
uint32_t shared_frame_candidates(const MetaballModel& m);
uint32_t shared_frame_table_size(uint32_t candidates);
// vertex_frame, frame_vertex and frame_count (init, after make_rest_blends).
void make_shared_frame_index(const MetaballModel& m, MetaballState* s);
// Every key's frame this step (skipped when features.shared_frames is off).
void make_shared_frames(const MetaballModel& m, MetaballState* s, DeformKernel kernel, const layer::Workers* workers);
// sum_j w_j s_j d_ij of vertex v, rounded as joint_region_frame rounds it
// (with balls_scaled as make_shared_frames set it this step).
fx::Vec3 vertex_disp_blend(const MetaballModel& m, const MetaballState& s, uint32_t v);
// The shared frame of v's key (its disp is the key's first vertex's), or
// null: v has none, or features.shared_frames is off.
const NormalBallFrame* shared_frame_of(const MetaballState& s, uint32_t v);
// joint_region_frame(m, s, v) from the shared frame of v's key, if v has one
// (false: none, or features.shared_frames off).
bool shared_vertex_frame(const MetaballModel& m, const MetaballState& s, uint32_t v, NormalBallFrame* f);

// Eq. (5) blended with eq. (1) for joint-region entry i (jv_*): v_lambda's
// frame f (joint_region_frame of the entry's vertex; a zero frame at
// w_alpha = 1) and R_eta, the bones' rotations blended by the entry's
// jv_blend, given. Writes out.position of jv_vertex[i] and
// s->jv_posed_laplacian[i]. The scalar specification.
void blend_joint_region_entry(const MetaballModel& m, std::span<const fx::Mat34> joint_model, const NormalBallFrame& f,
                              const fx::Quat& eta, uint32_t i, MetaballState* s, const skin::SkinnedVertices& out);
// The same for entries first + k, k < frames.size() (= eta.size()), by the
// kernel chosen: every kernel writes the same words. The AVX2 kernel
// (joint_blend_avx2.cpp) blends four entries at once and hands an entry it
// cannot prove exact to the specification.
void blend_joint_region_entries(const MetaballModel& m, std::span<const fx::Mat34> joint_model,
                                std::span<const NormalBallFrame* const> frames, std::span<const fx::Quat> eta,
                                uint32_t first, MetaballState* s, const skin::SkinnedVertices& out,
                                DeformKernel kernel);
#if defined(__x86_64__)
void blend_joint_region_entries_avx2(const MetaballModel& m, std::span<const fx::Mat34> joint_model,
                                     std::span<const NormalBallFrame* const> frames, std::span<const fx::Quat> eta,
                                     uint32_t first, MetaballState* s, const skin::SkinnedVertices& out);
#endif

// Where eq. (4)'s kernels hand the vertices whose balls turn differently
// (balls_turn_alike false), in ascending order, one call each.
struct TurnedVertices {
  void (*take)(void* context, uint32_t v);
  void* context;
};

// Eq. (4) alone: the scalar specification, and the AVX2 kernel
// (deform_avx2.cpp), which declines (returns false, writes nothing, hands
// nothing) when the model has more balls than it widens on its stack. Both
// leave the vertices of `skip` (ascending) unwritten: the joint-region
// vertices, which eq. (1) computes from their frames anyway. [begin, end):
// the vertices written (every vertex by default). turned: if given, leave
// unwritten, too, the vertices whose balls turn differently and hand them to
// it: the step computes them on the arc instead (deform.cpp,
// joint_region_frame).
void deform_normal_balls_scalar(const MetaballModel& m, const MetaballState& s, const skin::SkinnedVertices& out,
                                std::span<const uint32_t> skip = {}, uint32_t begin = 0, uint32_t end = UINT32_MAX,
                                const TurnedVertices* turned = nullptr);
// One vertex of the specification (the vector kernel's fallback).
void deform_normal_ball_vertex(const MetaballModel& m, const MetaballState& s, uint32_t v,
                               const skin::SkinnedVertices& out);
#if defined(__x86_64__)
bool deform_normal_balls_avx2(const MetaballModel& m, const MetaballState& s, const skin::SkinnedVertices& out,
                              std::span<const uint32_t> skip = {}, uint32_t begin = 0, uint32_t end = UINT32_MAX,
                              const TurnedVertices* turned = nullptr);
#endif

// True when every weighted ball of vertex v has the same rotation (the
// kernels' frame is then the rigid motion itself).
bool balls_turn_alike(const MetaballModel& m, const MetaballState& s, uint32_t v);

// The first index of `skip` (ascending) at or after vertex `begin`.
size_t first_skip_at(std::span<const uint32_t> skip, uint32_t begin);

// smoothing.cpp: stage 5.
void smooth_joint_region(const MetaballModel& m, MetaballState* s, const skin::SkinnedVertices& out);

// overlap.cpp: stage 6. Returns the number of projected vertices.
uint32_t resolve_overlaps(const MetaballModel& m, std::span<const fx::Mat34> joint_model, const MetaballState& s,
                          const skin::SkinnedVertices& out);

}  // namespace sinew::metaballs::detail
