#include "stage_table.hpp"

namespace sinew::pipeline {

static_assert(
    [] {
      for (uint32_t i = 0; i < kStageCount; ++i)
        if (static_cast<uint32_t>(kStages[i].stage) != i) return false;
      return true;
    }(),
    "kStages must list the stages in Stage order");

namespace stage_table_detail {
namespace {

void space(rig::MessageBuilder* out, bool* first) {
  if (!*first) out->text(" ");
  *first = false;
}

// A joint's name (NUL-terminated within kNameBytes by the loader), or jointN.
void joint_name(const rig::Rig& rig, uint32_t j, rig::MessageBuilder* out) {
  if (rig.names.empty() || j >= rig.names.size()) {
    out->text("joint").unsigned_number(j);
    return;
  }
  char name[rig::kNameBytes + 1] = {};
  for (uint32_t k = 0; k < rig::kNameBytes && rig.names[j][k] != '\0'; ++k) name[k] = rig.names[j][k];
  out->text(name);
}

}  // namespace

void describe_nothing(const rig::Rig&, const LayerSet&, rig::MessageBuilder*) {}

void describe_sph(const rig::Rig& rig, const LayerSet& layers, rig::MessageBuilder* out) {
  for (uint32_t i = 0; i < layers.sph_count; ++i) {
    if (i > 0) out->text(" ");
    out->text("sph(");
    joint_name(rig, layers.sph[i].model.joint.distal_joint, out);
    out->text(")");
  }
}

void describe_metaballs(const rig::Rig&, const LayerSet& layers, rig::MessageBuilder* out) {
  if (layers.has_metaballs) out->text("metaballs");
}

void describe_barnet(const rig::Rig&, const LayerSet& layers, rig::MessageBuilder* out) {
  bool first = true;
  for (uint32_t i = 0; i < layers.barnet_count; ++i) {
    space(out, &first);
    out->text("barnet");
  }
}

void describe_anatomy(const rig::Rig&, const LayerSet& layers, rig::MessageBuilder* out) {
  if (layers.has_muscles) out->text(layers.has_skin ? "anatomy(muscles, skin)" : "anatomy(muscles)");
}

}  // namespace stage_table_detail

const StageInfo* find_stage(const char* name, size_t name_length) {
  for (const StageInfo& s : kStages) {
    size_t n = 0;
    while (s.name[n] != '\0') ++n;
    if (n != name_length) continue;
    bool same = true;
    for (size_t k = 0; k < n && same; ++k) same = s.name[k] == name[k];
    if (same) return &s;
  }
  return nullptr;
}

void describe_layers(const rig::Rig& rig, const LayerSet& layers, char* out, size_t capacity) {
  rig::MessageBuilder m(out, capacity);
  bool any = false;
  for (const StageInfo& s : kStages) {
    if (s.stage == Stage::kSkinning || s.compiled(layers) == 0) continue;
    if (any) m.text(" ");
    s.describe(rig, layers, &m);
    any = true;
  }
  if (!any) m.text("none");
}

}  // namespace sinew::pipeline
