#include "barnet_state.hpp"

#include "barnet_refactor.hpp"
#include "barnet_validate.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"
#include "status_message.hpp"
#include "wrap.hpp"

namespace sinew::barnet {
namespace {

// Byte layout of the arena, every segment 8-byte aligned.
struct Layout {
  size_t first, offset, lower, recip, shift, q, skin, skin_columns, load, skinned, rest_direction, rest_magnitude, work,
      normal, scratch, total;
};

size_t align8(size_t v) { return (v + 7) & ~size_t{7}; }

// Entries of L in skyline storage: row i spans from its lowest free
// neighbour to the diagonal. Memoryless (free x bars); init-time only.
uint64_t profile_size(const BarnetModel& m, uint32_t free) {
  uint64_t total = 0;
  for (uint32_t i = 0; i < free; ++i) {
    uint32_t f = i;
    for (const BarRecord& b : m.bars) {
      if (b.a == i && b.b < f) f = b.b;
      if (b.b == i && b.a < f) f = b.a;
    }
    total += i - f;
  }
  return total;
}

Layout layout(const BarnetModel& m, uint32_t free, uint64_t profile) {
  Layout l{};
  size_t at = 0;
  auto take = [&at](size_t bytes) {
    const size_t start = at;
    at = align8(at + bytes);
    return start;
  };
  const size_t n = free;
  l.first = take(n * sizeof(uint32_t));
  l.offset = take((n + 1) * sizeof(uint32_t));
  l.lower = take(static_cast<size_t>(profile) * sizeof(int32_t));
  l.recip = take(n * sizeof(int64_t));
  l.shift = take(n * sizeof(int32_t));
  l.q = take(m.bars.size() * sizeof(ForceDensity));
  l.skin = take(m.joint_count * sizeof(fx::Mat34));
  l.skin_columns = take(m.joint_count * sizeof(SkinColumns));
  l.load = take(3 * n * sizeof(int64_t));
  l.skinned = take(3 * n * sizeof(fx::Len));
  l.rest_direction = take(n * sizeof(fx::Vec3));
  l.rest_magnitude = take(n * sizeof(int64_t));
  l.work = take(3 * n * sizeof(int64_t));  // the solve's three axes (the factor's scratch uses n)
  l.normal = take(m.triangles.size() * sizeof(TriangleFrame));
  l.scratch = take(m.nodes.size() * sizeof(uint32_t));
  l.total = at;
  return l;
}

template <typename T>
std::span<T> carve(unsigned char* base, size_t offset, size_t count) {
  // The layout keeps every offset 8-aligned and the arena is checked 8-aligned.
  return {static_cast<T*>(static_cast<void*>(base + offset)), count};
}

// Union-find over nodes with every fixed node merged into one ground node
// (the first fixed node): a free node is grounded iff it joins that set.
uint32_t find(std::span<uint32_t> parent, uint32_t v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];  // path halving
    v = parent[v];
  }
  return v;
}

// The rest load of every free node: p0 = D x0 + D_f x0_f (eq. (3)'s
// matrices, the model's own force densities, the bind-pose positions x0), the
// load under which the bind pose is the net's equilibrium (barnet_model.hpp).
// Row i of D x0 + D_f x0_f is sum over the bars at i of q (x0_i - x0_j):
// exact in Q.36 (q Q16.16 x Len Q12.20), each component below 16 x 2^24 x
// 2^33 = 2^61. Kept as a direction and a magnitude so the step can turn it
// with the node's blended bones without shrinking it.
void derive_rest_loads(const BarnetModel& m, uint32_t free, std::span<int64_t> sum[3], BarnetState* st) {
  for (size_t c = 0; c < 3; ++c)
    for (uint32_t i = 0; i < free; ++i) sum[c][i] = 0;
  for (const BarRecord& b : m.bars) {
    const fx::Vec3 pa = m.nodes[b.a].rest, pb = m.nodes[b.b].rest;
    const int64_t d[3] = {int64_t{pa.x} - pb.x, int64_t{pa.y} - pb.y, int64_t{pa.z} - pb.z};
    for (size_t c = 0; c < 3; ++c) {
      if (b.a < free) sum[c][b.a] += int64_t{b.q} * d[c];
      if (b.b < free) sum[c][b.b] -= int64_t{b.q} * d[c];
    }
  }
  for (uint32_t i = 0; i < free; ++i) {
    const int64_t p[3] = {sum[0][i], sum[1][i], sum[2][i]};
    uint64_t biggest = 0;
    for (int64_t v : p) biggest |= fx::magnitude(v);
    // |p| from components brought below 2^31 (floor shifts; a relative error
    // below 2^-30), then scaled back.
    int shift = 0;
    while ((biggest >> shift) >= (uint64_t{1} << 31)) ++shift;
    uint64_t squares = 0;
    for (int64_t v : p) {
      const uint64_t s = fx::magnitude(v) >> shift;
      squares += s * s;  // < 3 x 2^62
    }
    st->rest_magnitude[i] = static_cast<int64_t>(uint64_t{fx::isqrt_u64(squares)} << shift);  // < 2^62
    // The direction from components below 2^30 (normalize_to_unit's domain).
    const int dir_shift = shift + 1;
    fx::Vec3 unit{0, 0, 0};
    fx::normalize_to_unit(
        {static_cast<int32_t>(p[0] / (int64_t{1} << dir_shift)), static_cast<int32_t>(p[1] / (int64_t{1} << dir_shift)),
         static_cast<int32_t>(p[2] / (int64_t{1} << dir_shift))},
        &unit);
    st->rest_direction[i] = unit;
  }
}

LayerStatus check_graph(const BarnetModel& m, uint32_t free, std::span<uint32_t> scratch) {
  const uint32_t nodes = static_cast<uint32_t>(m.nodes.size());
  for (uint32_t i = 0; i < nodes; ++i) scratch[i] = 0;
  for (const BarRecord& b : m.bars) {
    ++scratch[b.a];
    ++scratch[b.b];
  }
  for (uint32_t i = 0; i < nodes; ++i)
    if (scratch[i] > kMaxBarsPerNode)
      return fail(LayerError::kBadCount, "nodes", i, "bars", "more than 16 bars on one node");
  const uint32_t ground = free;  // validate() guarantees a fixed node exists
  for (uint32_t i = 0; i < nodes; ++i) scratch[i] = i < free ? i : ground;
  for (const BarRecord& b : m.bars) {
    const uint32_t ra = find(scratch, b.a), rb = find(scratch, b.b);
    if (ra < rb) scratch[rb] = ra;
    if (rb < ra) scratch[ra] = rb;
  }
  const uint32_t g = find(scratch, ground);
  for (uint32_t i = 0; i < free; ++i)
    if (find(scratch, i) != g)
      return fail(LayerError::kSingular, "nodes", i, "kind",
                  "singular bar-net: this free node has no path of bars to a fixed node");
  return {};
}

}  // namespace

size_t barnet_state_bytes(const BarnetModel& model) {
  if (!barnet_validate_model(model).ok()) return 0;
  const uint32_t free = free_count(model);
  const uint64_t profile = profile_size(model, free);
  if (profile > kMaxProfile) return 0;
  return layout(model, free, profile).total;
}

LayerStatus barnet_init(const BarnetModel& model, void* arena, size_t arena_bytes, BarnetState* out) {
  LayerStatus s = barnet_validate_model(model);
  if (!s.ok()) return s;
  const uint32_t free = free_count(model);
  const uint64_t profile = profile_size(model, free);
  if (profile > kMaxProfile)
    return fail(LayerError::kBadCount,
                "bars: the factor's profile exceeds 2^18 entries (order free nodes along the net)");
  const Layout l = layout(model, free, profile);
  if (arena == nullptr || (reinterpret_cast<uintptr_t>(arena) & 7u) != 0 || arena_bytes < l.total)
    return fail(LayerError::kArena, "arena: null, not 8-byte aligned or smaller than barnet_state_bytes()");
  auto* base = static_cast<unsigned char*>(arena);

  BarnetState st;
  st.model = &model;
  st.free_count = free;
  st.profile = static_cast<uint32_t>(profile);
  st.factor.n = free;
  st.factor.first = carve<uint32_t>(base, l.first, free);
  st.factor.offset = carve<uint32_t>(base, l.offset, free + 1);
  st.factor.lower = carve<int32_t>(base, l.lower, static_cast<size_t>(profile));
  st.factor.recip = carve<int64_t>(base, l.recip, free);
  st.factor.shift = carve<int32_t>(base, l.shift, free);
  st.q = carve<ForceDensity>(base, l.q, model.bars.size());
  st.skin = carve<fx::Mat34>(base, l.skin, model.joint_count);
  st.skin_columns = carve<SkinColumns>(base, l.skin_columns, model.joint_count);
  for (size_t c = 0; c < 3; ++c) {
    st.load[c] = carve<int64_t>(base, l.load + c * free * sizeof(int64_t), free);
    st.skinned[c] = carve<fx::Len>(base, l.skinned + c * free * sizeof(fx::Len), free);
  }
  st.rest_direction = carve<fx::Vec3>(base, l.rest_direction, free);
  st.rest_magnitude = carve<int64_t>(base, l.rest_magnitude, free);
  st.work = carve<int64_t>(base, l.work, 3 * size_t{free});
  st.triangle = carve<TriangleFrame>(base, l.normal, model.triangles.size());
  st.kernel = vector_kernel_default();
  st.wrap_bounded = true;
  for (const WrapRecord& w : model.wrap) {
    const uint64_t sum = fx::magnitude(w.bary[0]) + fx::magnitude(w.bary[1]) + fx::magnitude(w.bary[2]);
    st.wrap_bounded = st.wrap_bounded && sum <= (uint64_t{1} << 31) && fx::magnitude(w.offset) <= (uint64_t{1} << 30);
  }
  const std::span<uint32_t> scratch = carve<uint32_t>(base, l.scratch, model.nodes.size());

  s = check_graph(model, free, scratch);
  if (!s.ok()) return s;
  derive_rest_loads(model, free, st.load, &st);

  // Skyline rows: first[i] = lowest free neighbour (or i).
  for (uint32_t i = 0; i < free; ++i) st.factor.first[i] = i;
  for (const BarRecord& b : model.bars) {
    if (b.a >= free || b.b >= free) continue;
    const uint32_t hi = b.a > b.b ? b.a : b.b, lo = b.a > b.b ? b.b : b.a;
    if (lo < st.factor.first[hi]) st.factor.first[hi] = lo;
  }
  st.factor.offset[0] = 0;
  for (uint32_t i = 0; i < free; ++i) st.factor.offset[i + 1] = st.factor.offset[i] + (i - st.factor.first[i]);

  // Assemble D = C^T Q C (eq. (3)) from the model's force densities.
  fx::Saturation unused;
  scale_force_densities(model, {}, st.q, unused);
  assemble_matrix(model.bars, st.q, st.factor);
  st.refactor_products = refactor_products(st.factor);
  const uint32_t bad = ldlt_factor(st.factor, st.work);
  if (bad < free)
    return fail(LayerError::kSingular, "nodes", bad, "kind",
                "singular bar-net: LDL^T pivot below 2^-24 at this free node");
  for (uint32_t i = 0; i < free; ++i) st.work[i] = 0;
  *out = st;
  return {};
}

}  // namespace sinew::barnet
