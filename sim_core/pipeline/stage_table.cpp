#include "stage_table.hpp"

namespace sinew::pipeline {

static_assert(
    [] {
      for (uint32_t i = 0; i < kStageCount; ++i)
        if (static_cast<uint32_t>(kStages[i].stage) != i) return false;
      return true;
    }(),
    "kStages must list the stages in Stage order");

bool LayerSet::empty() const {
  for (const StageInfo& s : kStages)
    if (s.stage != Stage::kSkinning && s.compiled(*this) > 0) return false;
  return true;
}

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
