#include "skin_state.hpp"

#include "sim_core/fixed/arena.hpp"
#include "sim_core/fixed/scalar.hpp"

namespace sinew::elastic_skin {
namespace {

fx::ArenaCarver layout(const SkinModel& model, void* base, size_t size, SkinState* s) {
  fx::ArenaCarver c(base, size);
  const size_t n = model.vertex_count;
  for (int a = 0; a < 3; ++a) s->position[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->anchor[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->previous[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->normal[a] = c.take<fx::Unit>(n);
  for (int a = 0; a < 3; ++a) s->sphere_centre[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->fat_offset[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->force[a] = c.take<int64_t>(n);
  s->weight = c.take<int64_t>(n);
  s->max_relax = c.take<fx::Len>(kMaxIterations);
  const bool dynamic = model.solver.mode == static_cast<uint8_t>(SkinMode::kDynamic);
  const size_t dn = dynamic ? n : 0, bands = dynamic ? model.bands.size() : 0;
  for (int a = 0; a < 3; ++a) s->fine[a] = c.take<int64_t>(dn);
  for (int a = 0; a < 3; ++a) s->velocity[a] = c.take<int64_t>(dn);
  for (int a = 0; a < 3; ++a) s->anchor_start[a] = c.take<fx::Len>(dn);
  for (int a = 0; a < 3; ++a) s->anchor_step[a] = c.take<int64_t>(dn);
  for (int a = 0; a < 3; ++a) s->band_start[a] = c.take<fx::Len>(bands);
  for (int a = 0; a < 3; ++a) s->band_end[a] = c.take<fx::Len>(bands);
  const bool surface = model.solver.fat_normal == static_cast<uint8_t>(FatNormal::kSurface);
  for (int a = 0; a < 3; ++a) s->surface_normal[a] = c.take<fx::Unit>(surface ? n : 0);
  const bool relaxation = dynamic && model.surface.integrator == static_cast<uint8_t>(SkinIntegrator::kRelaxation);
  const size_t rn = relaxation ? n : 0;
  for (int a = 0; a < 3; ++a) s->step_start[a] = c.take<int64_t>(rn);
  for (int a = 0; a < 3; ++a) s->bend[a] = c.take<int64_t>(rn);
  s->inverse_diagonal = c.take<int64_t>(rn);
  s->linear_gain = c.take<int64_t>(rn);
  for (int a = 0; a < 3; ++a) s->reaction_normal[a] = c.take<fx::Unit>(rn);
  s->reaction_floor = c.take<int64_t>(rn);
  s->incident_offset = c.take<uint32_t>(n + 1);
  s->incident_edge = c.take<uint32_t>(2 * model.edges.size());
  s->incident_at_b = c.take<uint8_t>(2 * model.edges.size());
  s->inverse_degree = c.take<int32_t>(rn);
  const size_t relaxation_slots = relaxation ? 2 * model.edges.size() : 0;
  s->incident_neighbour = c.take<uint32_t>(relaxation_slots);
  s->neighbour_inverse_degree = c.take<int32_t>(relaxation_slots);
  s->edge_gain = c.take<int64_t>(relaxation ? model.edges.size() : 0);
  s->band_offset = c.take<uint32_t>(n + 1);
  s->band_at = c.take<uint32_t>(model.bands.size());
  s->edge_stiffness = c.take<int32_t>(model.edges.size());
  for (int a = 0; a < 3; ++a) s->edge_pull[a] = c.take<fx::Len>(model.edges.size());
  s->moving_vertex = c.take<uint32_t>(n);
  s->moving_edge = c.take<uint32_t>(model.edges.size());
  s->mapped_vertex = c.take<uint32_t>(n);
  return c;
}

// The edges' CSR by vertex (a counting sort: deterministic, no
// allocation) and each vertex's 1 / degree. Edge endpoints are checked by
// the caller.
void fill_incidence(const SkinModel& model, SkinState* s) {
  const uint32_t n = model.vertex_count;
  for (uint32_t& o : s->incident_offset) o = 0;
  for (const Edge& e : model.edges) {
    ++s->incident_offset[e.a + 1];
    ++s->incident_offset[e.b + 1];
  }
  for (uint32_t v = 0; v < n; ++v) s->incident_offset[v + 1] += s->incident_offset[v];
  // A running cursor per vertex in its own start slot, shifted back after.
  for (uint32_t e = 0; e < model.edges.size(); ++e) {
    s->incident_at_b[s->incident_offset[model.edges[e].a]] = 0;
    s->incident_edge[s->incident_offset[model.edges[e].a]++] = e;
    s->incident_at_b[s->incident_offset[model.edges[e].b]] = 1;
    s->incident_edge[s->incident_offset[model.edges[e].b]++] = e;
  }
  for (uint32_t v = n; v > 0; --v) s->incident_offset[v] = s->incident_offset[v - 1];
  s->incident_offset[0] = 0;
  if (s->inverse_degree.empty()) return;
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t degree = s->incident_offset[v + 1] - s->incident_offset[v];
    s->inverse_degree[v] = degree == 0 ? 0 : static_cast<int32_t>(fx::div_round(fx::kUnitOne, degree));
  }
  for (uint32_t k = 0; k < s->incident_edge.size(); ++k) {
    const Edge& e = model.edges[s->incident_edge[k]];
    const uint32_t j = s->incident_at_b[k] == 0 ? e.b : e.a;
    s->incident_neighbour[k] = j;
    s->neighbour_inverse_degree[k] = s->inverse_degree[j];
  }
}

// The bands' CSR by vertex, in band order (a counting sort, as above).
// Band vertices are checked by the caller.
void fill_band_lists(const SkinModel& model, SkinState* s) {
  const uint32_t n = model.vertex_count;
  for (uint32_t& o : s->band_offset) o = 0;
  for (const RubberBand& b : model.bands) ++s->band_offset[b.vertex + 1];
  for (uint32_t v = 0; v < n; ++v) s->band_offset[v + 1] += s->band_offset[v];
  for (uint32_t i = 0; i < model.bands.size(); ++i) s->band_at[s->band_offset[model.bands[i].vertex]++] = i;
  for (uint32_t v = n; v > 0; --v) s->band_offset[v] = s->band_offset[v - 1];
  s->band_offset[0] = 0;
}

constexpr fx::Len kFar = INT32_MAX;  // a vertex no ring reaches

// Ring r about the region: every vertex one edge from ring r - 1 and not
// nearer (one pass over the edges, in edge order: deterministic).
void grow_ring(const SkinModel& model, std::span<fx::Len> ring, fx::Len r) {
  for (const Edge& e : model.edges) {
    if (ring[e.a] == r - 1 && ring[e.b] > r) ring[e.b] = r;
    if (ring[e.b] == r - 1 && ring[e.a] > r) ring[e.a] = r;
  }
}

// The vertices some ring reaches, ascending, into list; returns their count.
uint32_t list_reached(std::span<const fx::Len> ring, std::span<uint32_t> list) {
  uint32_t count = 0;
  for (uint32_t v = 0; v < ring.size(); ++v)
    if (ring[v] != kFar) list[count++] = v;
  return count;
}

// The static relaxation's moving vertices and edges and its mapped
// vertices (skin_state.hpp): the region, then kHaloRings breadth-first
// rings of edges about it, and one ring more for the mapped ones; each
// vertex's ring kept in previous[0] meanwhile (its scratch until the first
// round). False when the region is not ascending within the skin.
bool fill_moving(const SkinModel& model, SkinState* s) {
  const uint32_t n = model.vertex_count;
  const bool everything = model.region.empty() || model.solver.mode == static_cast<uint8_t>(SkinMode::kDynamic);
  const std::span<fx::Len> ring = s->previous[0].first(n);
  for (uint32_t v = 0; v < n; ++v) ring[v] = everything ? 0 : kFar;
  for (size_t i = 0; i < model.region.size() && !everything; ++i) {
    const uint32_t v = model.region[i];
    if (v >= n || (i > 0 && v <= model.region[i - 1])) return false;
    ring[v] = 0;
  }
  const auto halo = static_cast<fx::Len>(kHaloRings);
  for (fx::Len r = 1; r <= halo && !everything; ++r) grow_ring(model, ring, r);
  s->moving_vertices = list_reached(ring, s->moving_vertex);
  s->moving_edges = 0;
  for (uint32_t e = 0; e < model.edges.size(); ++e)
    if (ring[model.edges[e].a] != kFar || ring[model.edges[e].b] != kFar) s->moving_edge[s->moving_edges++] = e;
  if (!everything) grow_ring(model, ring, halo + 1);  // the moving edges' held ends
  s->mapped_vertices = list_reached(ring, s->mapped_vertex);
  return true;
}

}  // namespace

size_t skin_state_bytes(const SkinModel& model) {
  SkinState probe;
  return layout(model, nullptr, 0, &probe).needed();
}

LayerStatus skin_init(const SkinModel& model, void* memory, size_t bytes, SkinState* out) {
  if (out == nullptr) return muscle::layer_fail(LayerError::kArena, "skin state", -1, "", "null output");
  if (model.vertex_count > kMaxVertices)
    return muscle::layer_fail(LayerError::kBadValue, "skin model", -1, "vertex_count", "above 2^20", model.vertex_count,
                              true);
  if (!fx::aligned8(memory))
    return muscle::layer_fail(LayerError::kArena, "skin state", -1, "memory", "null or not 8-byte aligned");
  SkinState s;
  if (layout(model, memory, bytes, &s).failed())
    return muscle::layer_fail(LayerError::kArena, "skin state", -1, "bytes", "smaller than skin_state_bytes",
                              static_cast<int64_t>(bytes), true);
  s.vertex_count = model.vertex_count;
  for (const Edge& e : model.edges)
    if (e.a >= model.vertex_count || e.b >= model.vertex_count)
      return muscle::layer_fail(LayerError::kBadValue, "skin edge", -1, "a/b", "endpoint out of range");
  for (const RubberBand& b : model.bands)
    if (b.vertex >= model.vertex_count)
      return muscle::layer_fail(LayerError::kBadValue, "rubber band", -1, "vertex", "out of range");
  fill_incidence(model, &s);
  fill_band_lists(model, &s);
  if (!fill_moving(model, &s))
    return muscle::layer_fail(LayerError::kBadValue, "skin model", -1, "region",
                              "not ascending vertex indices of the skin");
  *out = s;
  return {};
}

}  // namespace sinew::elastic_skin
