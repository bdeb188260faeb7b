// The C API (sinew.h) over rig_init, layers_init and the pipeline.
#include <cstring>
#include <memory>

#include "sim_core/pipeline/pipeline.hpp"
#include "sim_core/pipeline/stage_table.hpp"
#include "sim_core/rig/rig.hpp"
#include "sinew.h"

struct sinew_rig {
  sinew::rig::Rig rig;
  sinew::pipeline::LayerSet layers;
};

struct sinew_pipeline {
  sinew::pipeline::Pipeline pipeline;
};

namespace {

constexpr size_t kAlign = 8;

size_t round_up(size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

bool aligned(const void* p) { return reinterpret_cast<uintptr_t>(p) % kAlign == 0; }

sinew_status status(int32_t code, const char* message) {
  sinew_status s{};
  s.code = code;
  if (message != nullptr) {
    const size_t n = std::strlen(message);
    const size_t m = n < sizeof(s.message) - 1 ? n : sizeof(s.message) - 1;
    std::memcpy(s.message, message, m);
    s.message[m] = '\0';
  }
  return s;
}

sinew_status ok() { return status(SINEW_OK, ""); }

template <typename Code>
sinew_status from(const sinew::fx::Status<Code>& st, int32_t code) {
  return st.ok() ? ok() : status(code, st.message);
}

sinew::pipeline::PipelineOptions pipeline_options(const sinew_pipeline_options* o) {
  sinew::pipeline::PipelineOptions options;
  if (o == nullptr) return options;
  options.tick_hz = o->tick_hz;
  for (uint32_t i = 1; i < sinew::pipeline::kStageCount; ++i)
    if ((o->stages_off >> i & 1u) != 0) options.stages.set(static_cast<sinew::pipeline::Stage>(i), false);
  return options;
}

}  // namespace

extern "C" {

sinew_status sinew_rig_bytes(const void* blob, size_t blob_bytes, size_t* bytes) {
  if (blob == nullptr || bytes == nullptr) return status(SINEW_ERROR_ARGUMENT, "sinew_rig_bytes: null argument");
  size_t arena = 0;
  const sinew::rig::LoadStatus st = sinew::rig::rig_validate(static_cast<const uint8_t*>(blob), blob_bytes, &arena);
  if (!st.ok()) return from(st, SINEW_ERROR_BLOB);
  *bytes = round_up(sizeof(sinew_rig)) + round_up(arena);
  return ok();
}

sinew_status sinew_rig_load(const void* blob, size_t blob_bytes, void* memory, size_t bytes, sinew_rig** out) {
  if (blob == nullptr || memory == nullptr || out == nullptr)
    return status(SINEW_ERROR_ARGUMENT, "sinew_rig_load: null argument");
  if (!aligned(memory)) return status(SINEW_ERROR_ARGUMENT, "sinew_rig_load: memory is not 8-byte aligned");
  size_t need = 0;
  sinew_status s = sinew_rig_bytes(blob, blob_bytes, &need);
  if (s.code != SINEW_OK) return s;
  if (bytes < need) return status(SINEW_ERROR_ARGUMENT, "sinew_rig_load: memory smaller than sinew_rig_bytes");
  auto* r = std::construct_at(static_cast<sinew_rig*>(memory));
  uint8_t* arena = static_cast<uint8_t*>(memory) + round_up(sizeof(sinew_rig));
  const sinew::rig::LoadStatus st = sinew::rig::rig_init(static_cast<const uint8_t*>(blob), blob_bytes, arena,
                                                         need - round_up(sizeof(sinew_rig)), &r->rig);
  if (!st.ok()) return from(st, SINEW_ERROR_BLOB);
  *out = r;
  return ok();
}

sinew_status sinew_layers_bytes(const sinew_rig* rig, const void* blob, size_t blob_bytes, size_t* bytes) {
  if (rig == nullptr || blob == nullptr || bytes == nullptr)
    return status(SINEW_ERROR_ARGUMENT, "sinew_layers_bytes: null argument");
  size_t arena = 0;
  const sinew::rig::LoadStatus st =
      sinew::pipeline::layers_validate(rig->rig, static_cast<const uint8_t*>(blob), blob_bytes, &arena);
  if (!st.ok()) return from(st, SINEW_ERROR_BLOB);
  *bytes = round_up(arena);
  return ok();
}

sinew_status sinew_layers_load(sinew_rig* rig, const void* blob, size_t blob_bytes, void* memory, size_t bytes) {
  if (rig == nullptr || blob == nullptr) return status(SINEW_ERROR_ARGUMENT, "sinew_layers_load: null argument");
  size_t need = 0;
  sinew_status s = sinew_layers_bytes(rig, blob, blob_bytes, &need);
  if (s.code != SINEW_OK) return s;
  if (need > 0 && (memory == nullptr || !aligned(memory) || bytes < need))
    return status(SINEW_ERROR_ARGUMENT,
                  "sinew_layers_load: memory null, misaligned or smaller than sinew_layers_bytes");
  return from(sinew::pipeline::layers_init(rig->rig, static_cast<const uint8_t*>(blob), blob_bytes, memory, bytes,
                                           &rig->layers),
              SINEW_ERROR_BLOB);
}

sinew_rig_info sinew_rig_get_info(const sinew_rig* rig) {
  sinew_rig_info info{};
  if (rig == nullptr) return info;
  info.joint_count = rig->rig.joint_count();
  info.input_count = rig->rig.input_count;
  info.external_input_count = rig->layers.external_count();
  info.vertex_count = rig->rig.vertex_count();
  for (const sinew::pipeline::StageInfo& s : sinew::pipeline::kStages)
    if (s.stage != sinew::pipeline::Stage::kSkinning && s.compiled(rig->layers) > 0) ++info.layer_count;
  return info;
}

uint32_t sinew_stage_count(void) { return sinew::pipeline::kStageCount; }

const char* sinew_stage_name(uint32_t stage) {
  return stage < sinew::pipeline::kStageCount ? sinew::pipeline::kStages[stage].name : nullptr;
}

size_t sinew_pipeline_state_bytes(const sinew_rig* rig, const sinew_pipeline_options* options) {
  if (rig == nullptr) return 0;
  return round_up(sizeof(sinew_pipeline)) +
         round_up(sinew::pipeline::pipeline_state_bytes(rig->rig, rig->layers, pipeline_options(options)));
}

sinew_status sinew_pipeline_init(const sinew_rig* rig, const sinew_pipeline_options* options, void* memory,
                                 size_t bytes, sinew_pipeline** out) {
  if (rig == nullptr || memory == nullptr || out == nullptr)
    return status(SINEW_ERROR_ARGUMENT, "sinew_pipeline_init: null argument");
  if (!aligned(memory)) return status(SINEW_ERROR_ARGUMENT, "sinew_pipeline_init: memory is not 8-byte aligned");
  const size_t need = sinew_pipeline_state_bytes(rig, options);
  if (bytes < need)
    return status(SINEW_ERROR_ARGUMENT, "sinew_pipeline_init: memory smaller than sinew_pipeline_state_bytes");
  auto* p = std::construct_at(static_cast<sinew_pipeline*>(memory));
  uint8_t* arena = static_cast<uint8_t*>(memory) + round_up(sizeof(sinew_pipeline));
  const sinew::pipeline::PipelineStatus st = sinew::pipeline::pipeline_init(
      rig->rig, rig->layers, pipeline_options(options), arena, need - round_up(sizeof(sinew_pipeline)), &p->pipeline);
  if (!st.ok()) return from(st, SINEW_ERROR_INIT);
  *out = p;
  return ok();
}

sinew_status sinew_pipeline_step(sinew_pipeline* pipeline, const int32_t* inputs, size_t input_count) {
  if (pipeline == nullptr || (inputs == nullptr && input_count > 0))
    return status(SINEW_ERROR_ARGUMENT, "sinew_pipeline_step: null argument");
  return from(sinew::pipeline::pipeline_step(&pipeline->pipeline, std::span<const int32_t>(inputs, input_count)),
              SINEW_ERROR_STEP);
}

sinew_vertices sinew_pipeline_vertices(const sinew_pipeline* pipeline) {
  sinew_vertices v{};
  if (pipeline == nullptr) return v;
  const auto& out = pipeline->pipeline.engine.vertices;
  v.x = out.position[0].data();
  v.y = out.position[1].data();
  v.z = out.position[2].data();
  v.count = static_cast<uint32_t>(out.position[0].size());
  return v;
}

}  // extern "C"
