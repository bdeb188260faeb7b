// Helpers every stage file shares (stage_fns.hpp).
#include <algorithm>

#include "sim_core/fixed/scalar.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {

PipelineStatus stage_fail(PipelineError e, const char* what, const char* detail, int64_t index) {
  PipelineStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text(what);
  if (index >= 0) m.text("[").number(index).text("]");
  if (detail != nullptr) m.text(": ").text(detail);
  return s;
}

void add_displacement(Pipeline* p, int axis, uint32_t v, fx::Len layer) {
  fx::Len& out = p->engine.vertices.position[axis][v];
  const int64_t sum = int64_t{out} + (int64_t{layer} - p->reference[axis][v]);
  const int32_t clamped = fx::sat_i32(sum);
  if (clamped != sum) ++p->saturated;
  out = clamped;
}

void add_displacements(Pipeline* p, int axis, std::span<const fx::Len> layer) {
  fx::Len* out = p->engine.vertices.position[axis].data();
  const fx::Len* reference = p->reference[axis].data();
  uint32_t saturated = 0;
  for (size_t v = 0; v < layer.size(); ++v) {
    const int64_t sum = int64_t{out[v]} + (int64_t{layer[v]} - reference[v]);
    const int32_t clamped = fx::sat_i32(sum);
    saturated += clamped != sum ? 1u : 0u;
    out[v] = clamped;
  }
  p->saturated += saturated;
}

void take_reference(Pipeline* p) {
  if (p->reference[0].empty()) return;
  for (int a = 0; a < 3; ++a)
    std::copy_n(p->engine.vertices.position[a].begin(), p->reference[a].size(), p->reference[a].begin());
}

}  // namespace sinew::pipeline::stages
