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

namespace {

// OR of |x| (as x ^ (x >> 31), within one of |x|) over n values: below 2^29
// for all three arrays means no sum out + (layer - reference) leaves
// (-2^31, 2^31), so the plain int32 sum is the saturating one.
uint32_t magnitudes(const fx::Len* a, const fx::Len* b, const fx::Len* c, size_t n) {
  uint32_t bits = 0;
  for (size_t i = 0; i < n; ++i)
    bits |= static_cast<uint32_t>((a[i] ^ (a[i] >> 31)) | (b[i] ^ (b[i] >> 31)) | (c[i] ^ (c[i] >> 31)));
  return bits;
}

}  // namespace

void add_displacements(Pipeline* p, int axis, std::span<const fx::Len> layer) {
  fx::Len* out = p->engine.vertices.position[axis].data();
  const fx::Len* reference = p->reference[axis].data();
  uint32_t saturated = 0;
  // In chunks: one that cannot saturate (checked first) takes plain int32
  // sums the compiler vectorises, any other the saturating int64 sums.
  constexpr size_t kChunk = 64;
  for (size_t begin = 0; begin < layer.size(); begin += kChunk) {
    const size_t end = layer.size() - begin < kChunk ? layer.size() : begin + kChunk;
    if (magnitudes(out + begin, layer.data() + begin, reference + begin, end - begin) < (uint32_t{1} << 29)) {
      for (size_t v = begin; v < end; ++v) out[v] = out[v] + (layer[v] - reference[v]);  // |.| <= 3 * 2^29 < 2^31
      continue;
    }
    for (size_t v = begin; v < end; ++v) {
      const int64_t sum = int64_t{out[v]} + (int64_t{layer[v]} - reference[v]);
      const int32_t clamped = fx::sat_i32(sum);
      saturated += clamped != sum ? 1u : 0u;
      out[v] = clamped;
    }
  }
  p->saturated += saturated;
}

void take_reference(Pipeline* p) {
  if (p->reference[0].empty()) return;
  for (int a = 0; a < 3; ++a)
    std::copy_n(p->engine.vertices.position[a].begin(), p->reference[a].size(), p->reference[a].begin());
}

}  // namespace sinew::pipeline::stages
