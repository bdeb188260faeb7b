// Loading of the layer sections (layer_format.hpp). Two passes, as the core
// loader: the structure of every section is checked against the blob before
// anything is read through a span (header, params size, array table, each
// array's alignment, element size, count and bounds; how many sections of an
// id, and the sections one needs), all from the sections' descriptors; then
// each section is copied into the arena and the stages load their models
// from it (stage_<name>_section.cpp), each handing its model to the layer's
// own validator, which checks every index and parameter against the rig.
// Nothing here names a layer.
#include <cstring>
#include <string_view>

#include "layer_set.hpp"
#include "section_view.hpp"
#include "sim_core/rig/message.hpp"
#include "stage_table.hpp"

namespace sinew::pipeline {
namespace {

using rig::LoadError;
using rig::LoadStatus;

constexpr uint64_t align8(uint64_t v) { return (v + 7u) & ~uint64_t{7}; }

LoadStatus fail(LoadError e, uint32_t id, uint32_t instance, const char* field, int64_t index, const char* what,
                int64_t value = 0, bool show_value = false) {
  return section_fail(e, id, instance, field, index, what, value, show_value);
}

// Every descriptor fits the loader's array table, and every version's arrays
// are a prefix of its section's list.
static_assert([] {
  for (const layer::SectionDescriptor* d : kLayerSections) {
    if (d->arrays.size() > kMaxLayerArrays) return false;
    for (const layer::SectionVersion& v : d->versions)
      if (v.array_count > d->arrays.size()) return false;
  }
  return true;
}());

// The section's header, array table and array bounds against its descriptor
// (sim_core/<layer>/<layer>_section.hpp): a version the descriptor lists,
// its params size and array count, each array's element size and maximum.
LoadStatus check_section(uint32_t id, uint32_t instance, const uint8_t* base, uint32_t size, SectionView* out) {
  out->id = id;
  out->instance = instance;
  out->base = base;
  out->size = size;
  if (size < sizeof(LayerSectionHeader))
    return fail(LoadError::kSectionSize, id, instance, "size", -1, "shorter than the 32-byte layer header", size, true);
  std::memcpy(&out->header, base, sizeof(LayerSectionHeader));
  const LayerSectionHeader& h = out->header;
  const layer::SectionDescriptor* descriptor = find_layer_section(id);
  const layer::SectionVersion* version = descriptor != nullptr ? descriptor->find(h.layer_version) : nullptr;
  if (version == nullptr)
    return fail(LoadError::kBadVersion, id, instance, "layer_version", -1, "unsupported layer section version",
                h.layer_version, true);
  if (h.params_size != version->params_size)
    return fail(LoadError::kSectionSize, id, instance, "params_size", -1, "does not match this layer's record",
                h.params_size, true);
  if (h.array_count != version->array_count)
    return fail(LoadError::kSectionSize, id, instance, "array_count", -1, "does not match this layer's arrays",
                h.array_count, true);
  const uint64_t table = sizeof(LayerSectionHeader) + align8(h.params_size);
  const uint64_t data = table + uint64_t{h.array_count} * sizeof(LayerArrayEntry);
  if (data > size)
    return fail(LoadError::kSectionSize, id, instance, "array_count", -1, "array table runs past the section",
                h.array_count, true);
  for (uint32_t i = 0; i < h.array_count; ++i) {
    LayerArrayEntry e;
    std::memcpy(&e, base + table + uint64_t{i} * sizeof(LayerArrayEntry), sizeof(e));
    const layer::SectionArray& spec = descriptor->arrays[i];
    if (e.element_size != spec.element_size)
      return fail(LoadError::kSectionSize, id, instance, spec.name, -1, "element size differs from this loader's",
                  e.element_size, true);
    if (e.count > spec.max_count)
      return fail(LoadError::kLimit, id, instance, spec.name, -1, "count exceeds the documented maximum", e.count,
                  true);
    const uint64_t end = uint64_t{e.offset} + uint64_t{e.count} * e.element_size;
    if (e.count > 0 && ((e.offset & 7u) != 0 || e.offset < data || end > size))
      return fail(LoadError::kSectionSize, id, instance, spec.name, -1, "outside the section or misaligned", e.offset,
                  true);
    out->arrays[i] = e;
  }
  return {};
}

// Walks the section table (already checked by rig_validate) and calls
// visit(id, instance, offset, size) for every layer section; enforces each
// descriptor's instance limit.
template <typename Visit>
LoadStatus for_each_layer_section(const uint8_t* blob, Visit visit) {
  constexpr size_t kKinds = std::size(kLayerSections);
  rig::FileHeader h;
  std::memcpy(&h, blob, sizeof(h));
  uint32_t seen[kKinds] = {};
  for (uint32_t i = 0; i < h.section_count; ++i) {
    rig::SectionEntry e;
    std::memcpy(&e, blob + h.section_table_offset + size_t{i} * sizeof(e), sizeof(e));
    size_t kind = kKinds;
    for (size_t k = 0; k < kKinds; ++k)
      if (kLayerSections[k]->id == e.id) kind = k;
    if (kind == kKinds) continue;
    const uint32_t limit = kLayerSections[kind]->max_instances;
    if (seen[kind] >= limit)
      return fail(LoadError::kSectionTable, e.id, seen[kind], "", -1, "more instances than the format allows", limit,
                  true);
    LoadStatus st = visit(e.id, seen[kind]++, e.offset, e.size);
    if (!st.ok()) return st;
  }
  return {};
}

LoadStatus check_external(const SectionView& v, std::span<const ExternalInputRecord> inputs, const rig::Rig& rig) {
  for (uint32_t i = 0; i < inputs.size(); ++i) {
    const ExternalInputRecord& r = inputs[i];
    if (std::memchr(r.name, 0, sizeof(r.name)) == nullptr || r.name[0] == '\0')
      return fail(LoadError::kBadValue, v.id, v.instance, "name", i, "empty or not NUL-terminated");
    if (std::memchr(r.unit, 0, sizeof(r.unit)) == nullptr)
      return fail(LoadError::kBadValue, v.id, v.instance, "unit", i, "not NUL-terminated");
    if (r.quantity > static_cast<uint32_t>(InputQuantity::kAcceleration))
      return fail(LoadError::kBadValue, v.id, v.instance, "quantity", i, "unknown quantity", r.quantity, true);
    if (r.min >= r.max) return fail(LoadError::kBadValue, v.id, v.instance, "min", i, "must be below max", r.min, true);
    for (uint32_t k = 0; k < i; ++k)
      if (std::strcmp(inputs[k].name, r.name) == 0)
        return fail(LoadError::kBadValue, v.id, v.instance, "name", i, "duplicate external input name");
    for (const auto& joint : rig.names)
      if (std::strcmp(joint, r.name) == 0)
        return fail(LoadError::kBadValue, v.id, v.instance, "name", i, "clashes with a joint name");
  }
  return {};
}

}  // namespace

LoadStatus layers_validate(const rig::Rig& rig, const uint8_t* blob, size_t size, size_t* arena_bytes) {
  (void)rig;
  size_t core_bytes = 0;
  LoadStatus st = rig::rig_validate(blob, size, &core_bytes);
  if (!st.ok()) return st;
  uint64_t bytes = 0;
  uint32_t present[std::size(kLayerSections)] = {};
  st = for_each_layer_section(blob, [&](uint32_t id, uint32_t instance, uint32_t offset, uint32_t sz) {
    SectionView v;
    LoadStatus s = check_section(id, instance, blob + offset, sz, &v);
    for (size_t k = 0; k < std::size(kLayerSections); ++k) present[k] += kLayerSections[k]->id == id ? 1u : 0u;
    bytes += align8(sz);
    return s;
  });
  if (!st.ok()) return st;
  // A section that is loaded with another (its descriptor's `needs`) is
  // refused without it.
  for (size_t k = 0; k < std::size(kLayerSections); ++k) {
    const layer::SectionDescriptor& d = *kLayerSections[k];
    if (present[k] == 0 || d.needs == 0) continue;
    const layer::SectionDescriptor* needed = find_layer_section(d.needs);
    bool found = false;
    for (size_t j = 0; j < std::size(kLayerSections); ++j) found |= kLayerSections[j]->id == d.needs && present[j] > 0;
    if (!found) {
      LoadStatus s;
      s.error = LoadError::kMissingSection;
      rig::MessageBuilder m(s.message, sizeof(s.message));
      m.text("rig blob: ")
          .text(d.name)
          .text("#0: needs a ")
          .text(needed != nullptr ? needed->name : "?")
          .text(" section, which the blob lacks");
      return s;
    }
  }
  *arena_bytes = static_cast<size_t>(bytes);
  return {};
}

LoadStatus layers_init(const rig::Rig& rig, const uint8_t* blob, size_t size, void* arena, size_t arena_bytes,
                       LayerSet* out) {
  size_t needed = 0;
  LoadStatus st = layers_validate(rig, blob, size, &needed);
  if (!st.ok()) return st;
  if ((needed > 0 && arena == nullptr) || arena_bytes < needed || (reinterpret_cast<uintptr_t>(arena) & 7u) != 0) {
    LoadStatus s;
    s.error = LoadError::kArenaTooSmall;
    rig::MessageBuilder m(s.message, sizeof(s.message));
    m.text("rig blob: layer arena: smaller than layers_validate's bytes or misaligned (")
        .number(static_cast<int64_t>(needed))
        .text(")");
    return s;
  }
  LayerSet set;
  uint8_t* a = static_cast<uint8_t*>(arena);
  size_t used = 0;
  // Copy every layer section first, keeping its view: the external inputs
  // are read by the stages' sections whatever their order.
  SectionView views[kMaxLayerSectionCount];
  uint32_t view_count = 0;
  st = for_each_layer_section(blob, [&](uint32_t id, uint32_t instance, uint32_t offset, uint32_t sz) {
    uint8_t* dst = a + used;
    if (sz > 0) std::memcpy(dst, blob + offset, sz);
    used += static_cast<size_t>(align8(sz));
    return check_section(id, instance, dst, sz, &views[view_count++]);
  });
  if (!st.ok()) return st;
  for (uint32_t i = 0; i < view_count; ++i)
    if (views[i].id == kSectionExternalInputs) {
      set.external = named<ExternalInputRecord, layer::array_ref(kExternalInputArraysList, "inputs")>(views[i]);
      if (!(st = check_external(views[i], set.external, rig)).ok()) return st;
    }
  // Then each stage loads its sections, in stage order.
  const std::span<const SectionView> loaded(views, view_count);
  for (const StageInfo& stage : kStages)
    if (!(st = stage.load(loaded, rig, &set)).ok()) return st;
  *out = set;
  return {};
}

uint32_t find_external_input(const LayerSet& layers, const char* name) {
  for (uint32_t i = 0; i < layers.external.size(); ++i)
    if (std::strcmp(layers.external[i].name, name) == 0) return i;
  return kNoExternalInput;
}

}  // namespace sinew::pipeline
