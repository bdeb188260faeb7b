// The frames on the arc shared by the vertices whose balls and weights are
// the same (kernels.hpp, "Shared frames"). joint_region_frame reads a
// vertex's balls, weights and displacements, and only the displacement
// blend differs between such vertices: the rotation and the centre are one
// function of (balls, weights). The rings of a tube share them (the built-in
// arm's counts: docs/metaballs.md, "Shared frames"), so a step
// makes each key's frame once and each vertex turns only its own
// displacement, word for word as joint_region_frame would.
#include "kernels.hpp"

namespace sinew::metaballs::detail {
namespace {

// A vertex that may need a frame on the arc: its weighted balls do not all
// follow one bone alone (make_rest_blends' vertex_bone), or it is a
// joint-region vertex below w_alpha = 1 (eq. 1 reads its frame every step).
// Marked in vertex_frame while the index is built.
constexpr uint32_t kCandidate = kNoFrame - 1;

bool same_slots(const MetaballModel& m, uint32_t a, uint32_t b) {
  const size_t ia = size_t{a} * kVertexBalls, ib = size_t{b} * kVertexBalls;
  for (uint32_t k = 0; k < kVertexBalls; ++k)
    if (m.vertex_ball[ia + k] != m.vertex_ball[ib + k] || m.vertex_weight[ia + k] != m.vertex_weight[ib + k])
      return false;
  return true;
}

// A fixed mix of the slots (unsigned, wrapping: defined), so the index, and
// every key's number, is the same on every machine.
uint64_t slots_hash(const MetaballModel& m, uint32_t v) {
  uint64_t h = 0;
  const size_t base = size_t{v} * kVertexBalls;
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    h = (h ^ m.vertex_ball[base + k]) * 0x9E3779B97F4A7C15ull;
    h = (h ^ static_cast<uint32_t>(m.vertex_weight[base + k])) * 0xBF58476D1CE4E5B9ull;
  }
  return h ^ (h >> 31);
}

}  // namespace

uint16_t vertex_one_bone(const MetaballModel& m, uint32_t v) {
  uint16_t bone = kNoBall;
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const size_t i = size_t{v} * kVertexBalls + k;
    if (m.vertex_weight[i] == 0) continue;  // its ball index is not checked by validation
    const uint16_t b = ball_bone(m, m.vertex_ball[i]);
    if (b == kNoBall || (bone != kNoBall && b != bone)) return kNoBall;
    bone = b;
  }
  return bone;
}

uint32_t shared_frame_candidates(const MetaballModel& m) {
  uint32_t n = 0;
  for (uint32_t v = 0; v < m.vertex_count; ++v) n += vertex_one_bone(m, v) == kNoBall ? 1u : 0u;
  for (uint32_t i = 0; i < m.jv_count(); ++i)
    n += m.jv_alpha[i] != fx::kUnitOne && vertex_one_bone(m, m.jv_vertex[i]) != kNoBall ? 1u : 0u;
  return n;
}

uint32_t shared_frame_table_size(uint32_t candidates) {
  uint32_t size = 1;
  while (size < 2 * candidates) size *= 2;  // candidates <= kMaxVertices: no overflow
  return size;
}

void make_shared_frame_index(const MetaballModel& m, MetaballState* s) {
  for (uint32_t v = 0; v < m.vertex_count; ++v) s->vertex_frame[v] = kNoFrame;
  for (uint32_t i = 0; i < m.jv_count(); ++i)
    if (m.jv_alpha[i] != fx::kUnitOne) s->vertex_frame[m.jv_vertex[i]] = kCandidate;
  for (uint32_t& slot : s->frame_table) slot = kNoFrame;
  const uint32_t mask = static_cast<uint32_t>(s->frame_table.size()) - 1;
  uint32_t count = 0;
  // Keys numbered in ascending vertex order of their first vertex.
  for (uint32_t v = 0; v < m.vertex_count; ++v) {
    if (s->vertex_frame[v] != kCandidate && s->vertex_bone[v] != kNoBall) continue;
    uint32_t at = static_cast<uint32_t>(slots_hash(m, v)) & mask;
    while (s->frame_table[at] != kNoFrame && !same_slots(m, s->frame_vertex[s->frame_table[at]], v))
      at = (at + 1) & mask;  // the table is at least twice the candidates: a free slot exists
    if (s->frame_table[at] == kNoFrame) {
      s->frame_table[at] = count;
      s->frame_vertex[count++] = v;
    }
    s->vertex_frame[v] = s->frame_table[at];
  }
  s->frame_count = count;
}

namespace {

struct SharedFramesJob {
  const MetaballModel* m;
  MetaballState* s;
  DeformKernel kernel;
};

void make_frame_range(void* context, uint32_t begin, uint32_t end) {
  const SharedFramesJob& j = *static_cast<const SharedFramesJob*>(context);
  const std::span<const uint32_t> vertices(j.s->frame_vertex.data() + begin, end - begin);
  joint_region_frames(*j.m, *j.s, vertices, j.s->shared_frame.subspan(begin, end - begin), j.kernel);
}

}  // namespace

void make_shared_frames(const MetaballModel& m, MetaballState* s, DeformKernel kernel, const layer::Workers* workers) {
  if (!s->features.shared_frames) return;
  bool scaled = false;
  for (const fx::Unit scale : s->ball_scale) scaled = scaled || scale != fx::kUnitOne;
  s->balls_scaled = scaled;
  SharedFramesJob job{&m, s, kernel};
  layer::run_ranges(workers, s->frame_count, make_frame_range, &job);
}

fx::Vec3 vertex_disp_blend(const MetaballModel& m, const MetaballState& s, uint32_t v) {
  if (!s.balls_scaled) return s.vertex_rest_disp[v];
  const size_t base = size_t{v} * kVertexBalls;
  bool scaled = false;
  for (uint32_t k = 0; k < kVertexBalls; ++k)
    scaled = scaled || (m.vertex_weight[base + k] != 0 && s.ball_scale[m.vertex_ball[base + k]] != fx::kUnitOne);
  if (!scaled) return s.vertex_rest_disp[v];  // sum_j w_j d_ij rounded as below (make_rest_blends)
  int64_t disp[3] = {0, 0, 0};
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const int64_t w = m.vertex_weight[base + k];
    if (w == 0) continue;
    const fx::Vec3 d0 = m.vertex_disp[base + k];
    const int64_t scale = s.ball_scale[m.vertex_ball[base + k]];
    int64_t dd[3] = {d0.x, d0.y, d0.z};
    for (int a = 0; a < 3; ++a) {
      if (scale != fx::kUnitOne) dd[a] = fx::round_shift(dd[a] * scale, fx::kUnitFracBits);  // |s d| < 2^32
      disp[a] += w * dd[a];
    }
  }
  const auto q30 = [](int64_t x) { return fx::sat_i32(fx::round_shift(x, fx::kUnitFracBits)); };
  return {q30(disp[0]), q30(disp[1]), q30(disp[2])};
}

const NormalBallFrame* shared_frame_of(const MetaballState& s, uint32_t v) {
  if (!s.features.shared_frames || s.vertex_frame.empty() || s.vertex_frame[v] == kNoFrame) return nullptr;
  return &s.shared_frame[s.vertex_frame[v]];
}

bool shared_vertex_frame(const MetaballModel& m, const MetaballState& s, uint32_t v, NormalBallFrame* f) {
  const NormalBallFrame* shared = shared_frame_of(s, v);
  if (shared == nullptr) return false;
  *f = *shared;
  f->disp = vertex_disp_blend(m, s, v);
  return true;
}

}  // namespace sinew::metaballs::detail
