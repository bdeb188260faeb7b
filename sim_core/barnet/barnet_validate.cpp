#include "barnet_validate.hpp"

#include "status_message.hpp"

namespace sinew::barnet {
namespace {

constexpr uint32_t kFixed = static_cast<uint32_t>(NodeKind::kFixed);

LayerStatus check_nodes(const BarnetModel& m) {
  bool seen_fixed = false;
  for (uint32_t i = 0; i < m.nodes.size(); ++i) {
    const NodeRecord& n = m.nodes[i];
    if (n.kind > kFixed) return fail(LayerError::kBadValue, "nodes", i, "kind", "must be 0 (free) or 1 (fixed)");
    if (n.kind == kFixed) seen_fixed = true;
    if (n.kind != kFixed && seen_fixed)
      return fail(LayerError::kBadValue, "nodes", i, "kind", "free nodes must precede every fixed node");
    if (n.influence_count == 0 || n.influence_count > kMaxNodeInfluences)
      return fail(LayerError::kBadValue, "nodes", i, "influence_count", "must be 1 to 4");
    int64_t sum = 0;
    for (uint32_t k = 0; k < n.influence_count; ++k) {
      if (n.joint[k] >= m.joint_count)
        return fail(LayerError::kBadIndex, "nodes", i, "joint", "is not a joint of the rig");
      if (n.weight[k] < 0) return fail(LayerError::kBadValue, "nodes", i, "weight", "is negative");
      sum += n.weight[k];
    }
    if (sum != fx::kUnitOne)
      return fail(LayerError::kBadValue, "nodes", i, "weight", "weights must sum to 2^30 exactly");
  }
  return {};
}

LayerStatus check_bars(const BarnetModel& m) {
  const uint32_t nodes = static_cast<uint32_t>(m.nodes.size());
  for (uint32_t i = 0; i < m.bars.size(); ++i) {
    const BarRecord& b = m.bars[i];
    if (b.a >= nodes) return fail(LayerError::kBadIndex, "bars", i, "a", "is not a node");
    if (b.b >= nodes) return fail(LayerError::kBadIndex, "bars", i, "b", "is not a node");
    if (b.a == b.b) return fail(LayerError::kBadIndex, "bars", i, "b", "a bar needs two distinct nodes");
    if (b.q <= 0) return fail(LayerError::kBadValue, "bars", i, "q", "force density must be positive");
    if (b.q < kMinForceDensity || b.q > kMaxForceDensity)
      return fail(LayerError::kBadValue, "bars", i, "q", "force density outside [2^-8, 256] (Q16.16)");
  }
  return {};
}

LayerStatus check_loads(const BarnetModel& m, uint32_t free) {
  for (uint32_t i = 0; i < m.loads.size(); ++i) {
    const LoadRecord& l = m.loads[i];
    if (l.node >= m.nodes.size()) return fail(LayerError::kBadIndex, "loads", i, "node", "is not a node");
    if (l.node >= free)
      return fail(LayerError::kBadIndex, "loads", i, "node", "is a fixed node (loads act on free nodes)");
    if (l.joint >= m.joint_count) return fail(LayerError::kBadIndex, "loads", i, "joint", "is not a joint of the rig");
    if (l.input >= m.input_count + m.external_count)
      return fail(LayerError::kBadIndex, "loads", i, "input",
                  "is neither a joint angle nor an external input of the rig");
    if (l.angle_lo == l.angle_hi)
      return fail(LayerError::kBadValue, "loads", i, "angle_hi", "must differ from angle_lo");
  }
  return {};
}

LayerStatus check_q_inputs(const BarnetModel& m) {
  for (uint32_t i = 0; i < m.q_inputs.size(); ++i) {
    const ForceDensityInput& r = m.q_inputs[i];
    if (r.input >= m.external_count)
      return fail(LayerError::kBadIndex, "q_inputs", i, "input", "is not an external input");
    if (r.bar_count == 0) return fail(LayerError::kBadValue, "q_inputs", i, "bar_count", "must be at least 1");
    if (uint64_t{r.first_bar} + r.bar_count > m.bars.size())
      return fail(LayerError::kBadIndex, "q_inputs", i, "bar_count", "the run of bars ends beyond the last bar");
  }
  return {};
}

LayerStatus check_mesh(const BarnetModel& m) {
  for (uint32_t i = 0; i < m.triangles.size(); ++i)
    for (uint32_t c = 0; c < 3; ++c)
      if (m.triangles[i].node[c] >= m.nodes.size())
        return fail(LayerError::kBadIndex, "triangles", i, "node", "is not a node");
  for (uint32_t i = 0; i < m.wrap.size(); ++i) {
    const WrapRecord& w = m.wrap[i];
    if (w.vertex >= m.vertex_count) return fail(LayerError::kBadIndex, "wrap", i, "vertex", "is not a skin vertex");
    if (w.triangle >= m.triangles.size())
      return fail(LayerError::kBadIndex, "wrap", i, "triangle", "is not a control triangle");
    const int64_t sum = int64_t{w.bary[0]} + w.bary[1] + w.bary[2];
    if (sum != fx::kUnitOne) return fail(LayerError::kBadValue, "wrap", i, "bary", "must sum to 2^30 exactly");
  }
  return {};
}

}  // namespace

uint32_t free_count(const BarnetModel& model) {
  uint32_t n = 0;
  while (n < model.nodes.size() && model.nodes[n].kind != kFixed) ++n;
  return n;
}

LayerStatus barnet_validate_model(const BarnetModel& m) {
  if (m.nodes.empty()) return fail(LayerError::kBadCount, "nodes: a bar-net needs at least one node");
  if (m.nodes.size() > kMaxNodes) return fail(LayerError::kBadCount, "nodes: more than 4096");
  if (m.bars.size() > kMaxBars) return fail(LayerError::kBadCount, "bars: more than 16384");
  if (m.loads.size() > kMaxLoads) return fail(LayerError::kBadCount, "loads: more than 1024");
  if (m.triangles.size() > kMaxTriangles) return fail(LayerError::kBadCount, "triangles: more than 8192");
  if (m.wrap.size() > kMaxWrapVertices) return fail(LayerError::kBadCount, "wrap: more than 2^20 vertices");
  if (m.joint_count == 0 || m.joint_count > kMaxJoints)
    return fail(LayerError::kBadCount, "joint_count: must be 1 to 1024");
  if (m.external_count > kMaxExternalInputs) return fail(LayerError::kBadCount, "external_count: more than 64");
  if (m.q_inputs.size() > kMaxForceDensityInputs) return fail(LayerError::kBadCount, "q_inputs: more than 64");
  if (m.inverse_bind.size() != m.joint_count)
    return fail(LayerError::kBadIndex, "inverse_bind: needs one matrix per joint (joint_count)");
  LayerStatus s = check_nodes(m);
  if (!s.ok()) return s;
  const uint32_t free = free_count(m);
  if (free > kMaxFreeNodes) return fail(LayerError::kBadCount, "nodes: more than 1024 free nodes");
  if (free == m.nodes.size())
    return fail(LayerError::kSingular,
                "nodes: singular bar-net, no fixed node (D = C^T Q C has the constant vector in its kernel)");
  s = check_bars(m);
  if (!s.ok()) return s;
  s = check_loads(m, free);
  if (!s.ok()) return s;
  s = check_q_inputs(m);
  if (!s.ok()) return s;
  return check_mesh(m);
}

LayerStatus barnet_validate(const BarnetModel& m, const rig::Rig& rig) {
  if (m.joint_count != rig.joint_count()) return fail(LayerError::kBadCount, "joint_count: differs from the rig's");
  if (m.input_count != rig.input_count) return fail(LayerError::kBadCount, "input_count: differs from the rig's");
  if (m.vertex_count != rig.vertex_count()) return fail(LayerError::kBadCount, "vertex_count: differs from the rig's");
  return barnet_validate_model(m);
}

}  // namespace sinew::barnet
