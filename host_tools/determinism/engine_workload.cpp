#include "engine_workload.hpp"

#include <chrono>
#include <cstring>
#include <vector>

#include "hal/sim/sweep.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "output_hash.hpp"
#include "sim_core/engine/engine.hpp"

namespace sinew::determinism {

int32_t trajectory_input(uint32_t input, uint32_t step) { return hal::sim::sweep_input(input, step); }

bool run_engine_workload(const std::string& rig_name, int steps, EngineRun* out, std::string* error) {
  rigc::RigSpec spec;
  if (!rigc::builtin_rig(rig_name, rigc::SkinChoice::kDualQuaternion, &spec))
    return *error = "unknown built-in rig " + rig_name, false;
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  if (!rigc::compile_rig(spec, &bytes, &report, error)) return false;
  std::vector<uint64_t> blob(bytes.size() / 8 + 1);
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(blob.data());
  size_t rig_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(data, bytes.size(), &rig_bytes);
  if (!st.ok()) return *error = st.message, false;
  std::vector<uint64_t> rig_arena(rig_bytes / 8 + 1);
  rig::Rig rig;
  st = rig::rig_init(data, bytes.size(), rig_arena.data(), rig_arena.size() * 8, &rig);
  if (!st.ok()) return *error = st.message, false;
  std::vector<uint64_t> engine_arena(engine::engine_arena_bytes(rig) / 8 + 1);
  engine::Engine e;
  if (!engine::engine_init(rig, engine_arena.data(), engine_arena.size() * 8, &e))
    return *error = "engine arena", false;

  OutputHash blob_hash;
  for (uint8_t b : bytes) blob_hash.add_u32(b);
  out->blob_hash = blob_hash.digest();
  out->vertices = rig.vertex_count();
  std::vector<int32_t> inputs(rig.input_count);
  OutputHash h;
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) {
    for (uint32_t i = 0; i < rig.input_count; ++i) inputs[i] = trajectory_input(i, static_cast<uint32_t>(s));
    engine::engine_step(&e, inputs);
    out->clamped_dofs += e.stats.clamped_dofs;
    for (int c = 0; c < 3; ++c)
      for (uint32_t v = 0; v < rig.vertex_count(); ++v) h.add_i32(e.vertices.position[c][v]);
    if (!e.vertices.normal[0].empty())
      for (int c = 0; c < 3; ++c)
        for (uint32_t v = 0; v < rig.vertex_count(); ++v) h.add_i32(e.vertices.normal[c][v]);
    for (uint32_t j = 0; j < rig.joint_count(); ++j) h.add_u32(e.joint_flags[j]);
  }
  out->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out->output_hash = h.digest();
  return true;
}

}  // namespace sinew::determinism
