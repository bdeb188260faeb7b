#include "run_setup.hpp"

#include <algorithm>

#include "hal/units/float_to_fixed.hpp"
#include "sim_core/pipeline/stage_table.hpp"

namespace sinew::firmware {

std::vector<InputLimits> input_limits(const LoadedRig& rig, const DaemonConfig& config, uint64_t) {
  std::vector<InputLimits> limits(rig.input_count());
  const auto timeout = static_cast<uint64_t>(config.timeout_factor * config.default_period_ms * 1e6);
  // 0..180 degrees (the config's range): the largest is just under a half turn.
  const int64_t margin_angle = units::signed_angle_from_degrees(config.range_margin_deg).value;
  for (const rig::JointRecord& j : rig.rig.joints) {
    for (uint32_t d = 0; d < j.dof_count; ++d) {
      InputLimits& l = limits[j.first_input + d];
      const int64_t span = int64_t{j.dof_max[d]} - j.dof_min[d];
      const int64_t margin = j.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation) ? margin_angle : span / 10;
      l.min = static_cast<int32_t>(std::max<int64_t>(INT32_MIN, j.dof_min[d] - margin));
      l.max = static_cast<int32_t>(std::min<int64_t>(INT32_MAX, j.dof_max[d] + margin));
      l.timeout_ns = timeout;
    }
  }
  for (size_t k = 0; k < rig.external.size(); ++k) {
    const ExternalInput& e = rig.external[k];
    InputLimits& l = limits[rig.rig.input_count + k];
    const int64_t margin = (int64_t{e.max} - e.min) / 10;
    l.min = static_cast<int32_t>(std::max<int64_t>(INT32_MIN, e.min - margin));
    l.max = static_cast<int32_t>(std::min<int64_t>(INT32_MAX, e.max + margin));
    l.timeout_ns = timeout;
  }
  return limits;
}

bool layer_options(const DaemonConfig& config, const LoadedRig& rig, pipeline::PipelineOptions* out,
                   std::string* error) {
  for (const pipeline::StageInfo& s : pipeline::kStages)
    if (s.stage != pipeline::Stage::kSkinning && config.layers.stages.has(s.stage) && s.compiled(rig.layers) == 0)
      return *error = std::string("[layers] ") + s.name +
                      " = true, but the rig carries no such layer (compile it with " + s.rig_sections +
                      " in the rig's spec; this rig has: " + describe_layers(rig) + ")",
             false;
  pipeline::PipelineOptions o = config.layers;
  o.tick_hz = config.rate_hz;
  *out = o;
  return true;
}

bool pipeline_accepts(const LoadedRig& rig, const pipeline::PipelineOptions& options, std::string* error) {
  std::vector<uint64_t> arena(pipeline::pipeline_state_bytes(rig.rig, rig.layers, options) / 8 + 1, 0);
  pipeline::Pipeline p;
  const pipeline::PipelineStatus s =
      pipeline::pipeline_init(rig.rig, rig.layers, options, arena.data(), arena.size() * 8, &p);
  if (!s.ok()) return *error = std::string("layers: ") + s.message, false;
  return true;
}

}  // namespace sinew::firmware
