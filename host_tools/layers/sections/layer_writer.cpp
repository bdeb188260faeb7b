#include "layer_writer.hpp"

#include <cstring>
#include <string>
#include <string_view>

#include "host_tools/layers/sections/section_builder.hpp"
#include "sim_core/pipeline/layer_set.hpp"
#include "sim_core/rig/crc32c.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::layers {
namespace {

constexpr size_t align8(size_t v) { return (v + 7u) & ~size_t{7}; }

}  // namespace

LayerSection external_inputs_section(std::span<const pipeline::ExternalInputRecord> inputs) {
  SectionBuilder b(pipeline::kExternalInputSection, pipeline::kLayerSectionVersion, 0, nullptr, 0);
  b.array("inputs", inputs);
  return b.finish();
}

bool append_layer_sections(std::vector<uint8_t>* blob, const std::vector<LayerSection>& sections, std::string* error) {
  namespace fmt = sinew::rig;
  if (sections.empty()) return true;
  for (const LayerSection& s : sections)
    if (!s.problem.empty()) return *error = s.problem, false;
  fmt::FileHeader h;
  if (blob->size() < sizeof(h)) return *error = "internal: core blob too short", false;
  std::memcpy(&h, blob->data(), sizeof(h));
  std::vector<fmt::SectionEntry> table(h.section_count);
  std::memcpy(table.data(), blob->data() + h.section_table_offset, table.size() * sizeof(fmt::SectionEntry));
  const size_t count = table.size() + sections.size();
  if (count > fmt::kMaxSections)
    return *error = "rig has " + std::to_string(count) + " sections, more than the format's " +
                    std::to_string(fmt::kMaxSections),
           false;
  // New layout: header, the longer table, the core payloads, the layer payloads.
  std::vector<uint8_t> out(sizeof(fmt::FileHeader) + count * sizeof(fmt::SectionEntry), 0);
  std::vector<fmt::SectionEntry> new_table;
  for (const fmt::SectionEntry& e : table) {
    const size_t at = align8(out.size());
    out.resize(at + e.size, 0);
    std::memcpy(out.data() + at, blob->data() + e.offset, e.size);
    new_table.push_back({e.id, static_cast<uint32_t>(at), e.size, 0});
  }
  for (const LayerSection& s : sections) {
    const size_t at = align8(out.size());
    out.resize(at + s.payload.size(), 0);
    std::memcpy(out.data() + at, s.payload.data(), s.payload.size());
    new_table.push_back({s.id, static_cast<uint32_t>(at), static_cast<uint32_t>(s.payload.size()), 0});
  }
  out.resize(align8(out.size()), 0);
  if (out.size() > UINT32_MAX) return *error = "rig blob larger than 4 GiB", false;
  h.version_minor = 1;  // layer sections: format 1.1
  h.total_size = static_cast<uint32_t>(out.size());
  h.section_count = static_cast<uint32_t>(count);
  h.section_table_offset = sizeof(fmt::FileHeader);
  h.crc32c = 0;
  std::memcpy(out.data(), &h, sizeof(h));
  std::memcpy(out.data() + sizeof(h), new_table.data(), count * sizeof(fmt::SectionEntry));
  const uint32_t crc = fmt::crc32c(0, out.data(), out.size());
  std::memcpy(out.data() + offsetof(fmt::FileHeader, crc32c), &crc, 4);

  // Round trip through the runtime loaders: the compiler never emits a blob
  // the board would reject.
  std::vector<uint64_t> aligned(out.size() / 8 + 1);
  std::memcpy(aligned.data(), out.data(), out.size());
  const auto* data = reinterpret_cast<const uint8_t*>(aligned.data());
  size_t rig_bytes = 0, layer_bytes = 0;
  fmt::LoadStatus st = fmt::rig_validate(data, out.size(), &rig_bytes);
  std::vector<uint64_t> rig_arena(rig_bytes / 8 + 1);
  fmt::Rig rig;
  if (st.ok()) st = fmt::rig_init(data, out.size(), rig_arena.data(), rig_arena.size() * 8, &rig);
  if (st.ok()) st = pipeline::layers_validate(rig, data, out.size(), &layer_bytes);
  std::vector<uint64_t> layer_arena(layer_bytes / 8 + 1);
  pipeline::LayerSet set;
  if (st.ok()) st = pipeline::layers_init(rig, data, out.size(), layer_arena.data(), layer_arena.size() * 8, &set);
  if (!st.ok()) return *error = std::string("compiled layers rejected by the runtime loader: ") + st.message, false;
  *blob = std::move(out);
  return true;
}

}  // namespace sinew::layers
