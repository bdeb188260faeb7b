#include "pipeline.hpp"

#include <algorithm>

#include "sim_core/fixed/arena.hpp"
#include "sim_core/fixed/quat.hpp"
#include "sim_core/fixed/trig.hpp"
#include "stage_table.hpp"

namespace sinew::pipeline {
namespace {

using stages::stage_fail;

// The stages that run: skinning, and every layer the rig carries that the
// options leave on.
StageSet stages_on(const LayerSet& layers, const PipelineOptions& o) {
  StageSet on = StageSet::none();
  for (const StageInfo& s : kStages)
    on.set(s.stage, s.stage == Stage::kSkinning || (o.stages.has(s.stage) && s.compiled(layers) > 0));
  return on;
}

// One layout for counting and carving: each stage's block (in Stage order),
// then the buffers the stages share. A stage carves its own state inside its
// block (StageInfo::init).
fx::ArenaCarver layout(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& o, void* base, size_t size,
                       Pipeline* p, uint8_t* blocks[kStageCount], size_t block_bytes[kStageCount]) {
  fx::ArenaCarver c(base, size);
  const StageSet on = stages_on(layers, o);
  for (const StageInfo& s : kStages) {
    const auto i = static_cast<uint32_t>(s.stage);
    block_bytes[i] = on.has(s.stage) ? s.state_bytes(rig, layers, o) : 0;
    blocks[i] = c.raw(block_bytes[i]);
  }
  stages::SharedNeeds needs;
  for (const StageInfo& s : kStages) {
    if (!on.has(s.stage)) continue;
    const stages::SharedNeeds n = s.shares(rig, layers);
    needs.reference = needs.reference || n.reference;
    needs.bent_pose = needs.bent_pose || n.bent_pose;
    needs.scratch_vertices = std::max(needs.scratch_vertices, n.scratch_vertices);
    needs.node_outputs = std::max(needs.node_outputs, n.node_outputs);
  }
  p->flexed = c.take<int32_t>(needs.bent_pose ? rig.input_count : 0);
  p->bent = c.take<skeleton::LocalPose>(needs.bent_pose ? rig.joint_count() : 0);
  p->measured = c.take<int32_t>(rig.input_count + layers.external_count());
  // Sizes from the options, never from the blocks (null when only counting).
  for (int a = 0; a < 3; ++a) {
    p->reference[a] = c.take<fx::Len>(needs.reference ? rig.vertex_count() : 0);
    p->scratch[a] = c.take<fx::Len>(needs.scratch_vertices);
    p->node_outputs[a] = c.take<fx::Len>(needs.node_outputs);
  }
  return c;
}

}  // namespace

const char* stage_name(Stage s) {
  const uint32_t i = static_cast<uint32_t>(s);
  return i < kStageCount ? kStages[i].name : "unknown";
}

size_t pipeline_state_bytes(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options) {
  Pipeline probe;
  uint8_t* blocks[kStageCount] = {};
  size_t block_bytes[kStageCount] = {};
  return layout(rig, layers, options, nullptr, 0, &probe, blocks, block_bytes).needed();
}

PipelineStatus pipeline_init(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options, void* arena,
                             size_t arena_bytes, Pipeline* out) {
  if (out == nullptr) return stage_fail(PipelineError::kArena, "pipeline", "no pipeline to initialise");
  if (!fx::aligned8(arena)) return stage_fail(PipelineError::kArena, "pipeline", "arena missing or misaligned");
  // Every number option within the range its row declares.
  for (const StageOption& option : kStageOptions) {
    if (option.kind != OptionKind::kNumber) continue;
    const uint32_t v = option_value(option, options);
    if (v >= option.min && v <= option.max) continue;
    PipelineStatus st;
    st.error = PipelineError::kBadModel;
    rig::MessageBuilder m(st.message, sizeof(st.message));
    m.text("pipeline: ").text(option.key).text(" = ").unsigned_number(v).text(" is outside ");
    m.unsigned_number(option.min).text("..").unsigned_number(option.max);
    return st;
  }
  const StageSet on = stages_on(layers, options);
  for (const StageInfo& s : kStages) {
    if (!on.has(s.stage)) continue;
    const PipelineStatus st = s.validate(rig, layers);
    if (!st.ok()) return st;
  }
  // Built in place: the layer states keep pointers into the pipeline.
  Pipeline& p = *out;
  p = Pipeline{};
  p.rig = &rig;
  p.layers = &layers;
  p.options = options;
  uint8_t* blocks[kStageCount] = {};
  size_t block_bytes[kStageCount] = {};
  const fx::ArenaCarver c = layout(rig, layers, options, arena, arena_bytes, &p, blocks, block_bytes);
  if (c.failed()) return stage_fail(PipelineError::kArena, "pipeline", "arena smaller than pipeline_state_bytes");
  p.input_count = rig.input_count + layers.external_count();
  for (const StageInfo& s : kStages) {
    if (!on.has(s.stage)) continue;
    const auto i = static_cast<uint32_t>(s.stage);
    const PipelineStatus st = s.init(&p, blocks[i], block_bytes[i]);
    if (!st.ok()) return st;
  }
  p.on = on;
  return {};
}

bool pipeline_stage_on(const Pipeline& p, Stage s) { return p.on.has(s); }

void pipeline_set_measured_inputs(Pipeline* p, std::span<const uint8_t> measured) {
  p->engine.measured_inputs = measured;
}

namespace {

// Twist of q about a unit axis: 2 atan2(q.v . axis, q.w), a binary angle.
fx::Angle twist_angle(const fx::Quat& q, const fx::Unit axis[3]) {
  const int64_t along = int64_t{q.x} * axis[0] + int64_t{q.y} * axis[1] + int64_t{q.z} * axis[2];
  const int32_t y = fx::sat_i32(fx::round_shift(along, fx::kUnitFracBits));
  return static_cast<fx::Angle>(2u * fx::atan2_angle(y, q.w));
}

void measure_dofs(Pipeline* p) {
  const rig::Rig& rig = *p->rig;
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    const rig::JointRecord& r = rig.joints[j];
    const skeleton::LocalPose& l = p->engine.locals[j];
    const fx::Quat rest{r.rest_rotation[0], r.rest_rotation[1], r.rest_rotation[2], r.rest_rotation[3]};
    const fx::Quat relative = fx::mul(fx::conjugate(rest), l.rotation);
    for (uint32_t d = 0; d < r.dof_count; ++d) {
      int32_t value = 0;
      if (r.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation)) {
        value = static_cast<int32_t>(twist_angle(relative, r.dof_axis[d]));
      } else {
        const int64_t offset = (int64_t{l.translation.x} - r.rest_translation[0]) * r.dof_axis[d][0] +
                               (int64_t{l.translation.y} - r.rest_translation[1]) * r.dof_axis[d][1] +
                               (int64_t{l.translation.z} - r.rest_translation[2]) * r.dof_axis[d][2];
        value = fx::sat_i32(fx::round_shift(offset, fx::kUnitFracBits));
      }
      p->measured[r.first_input + d] = value;
    }
  }
}

}  // namespace

namespace {

uint64_t probe_now(const StepProbe* probe) {
  return probe != nullptr && probe->now_ns != nullptr ? probe->now_ns(probe->context) : 0;
}

void stage_done(const StepProbe* probe, StepReport* report, Stage s, uint64_t started, const Pipeline& p) {
  if (report != nullptr) {
    report->ran.set(s, true);
    if (probe != nullptr && probe->now_ns != nullptr)
      report->stage_ns[static_cast<uint32_t>(s)] = probe->now_ns(probe->context) - started;
  }
  if (probe != nullptr && probe->after_stage != nullptr) probe->after_stage(probe->context, s, p);
}

// Stages first..last that are on, in order; the first failure ends the tick.
// When a stage that is on is parallel, the workers are told a step using
// them runs (begin_step / end_step, sim_core/layer/workers.hpp) from the
// start of the stage before the first parallel one, so they are awake when
// its first loop comes, to the end of the last parallel one.
PipelineStatus run_stages(Pipeline* p, std::span<const int32_t> inputs, Stage first, const StepProbe* probe,
                          StepReport* report) {
  const layer::Workers* w = p->options.workers;
  const bool pool = w != nullptr && w->parts > 1 && w->begin_step != nullptr && w->end_step != nullptr;
  uint32_t wake_at = kStageCount, last_parallel = kStageCount, previous_on = kStageCount;
  if (pool) {
    for (uint32_t i = static_cast<uint32_t>(first); i < kStageCount; ++i) {
      if (!p->on.has(static_cast<Stage>(i))) continue;
      if (kStages[i].parallel) {
        if (wake_at == kStageCount) wake_at = previous_on != kStageCount ? previous_on : i;
        last_parallel = i;
      }
      previous_on = i;
    }
  }
  bool awake = false;
  PipelineStatus st;
  for (uint32_t i = static_cast<uint32_t>(first); i < kStageCount && st.ok(); ++i) {
    const auto s = static_cast<Stage>(i);
    if (!p->on.has(s)) continue;
    if (i == wake_at) {
      w->begin_step(w->pool);
      awake = true;
    }
    const uint64_t started = probe_now(probe);
    st = kStages[i].step(p, inputs);
    stage_done(probe, report, s, started, *p);
    if (awake && i == last_parallel) {
      w->end_step(w->pool);
      awake = false;
    }
  }
  if (awake) w->end_step(w->pool);
  return st;
}

void begin_report(StepReport* report) {
  if (report == nullptr) return;
  for (uint64_t& ns : report->stage_ns) ns = 0;
  report->ran = StageSet::none();
  std::fill(report->input_flags.begin(), report->input_flags.end(), uint8_t{0});
}

// Each stage that is on flags the inputs it concerns (StageInfo::flag_inputs).
void report_input_flags(const Pipeline& p, StepReport* report) {
  if (report == nullptr || report->input_flags.empty()) return;
  for (const StageInfo& s : kStages)
    if (p.on.has(s.stage)) s.flag_inputs(p, report->input_flags);
}

}  // namespace

PipelineStatus pipeline_step(Pipeline* p, std::span<const int32_t> inputs, const StepProbe* probe, StepReport* report) {
  begin_report(report);
  if (p == nullptr || p->rig == nullptr) return stage_fail(PipelineError::kArena, "pipeline", "not initialised");
  if (inputs.size() < p->input_count)
    return stage_fail(PipelineError::kBadInput, "pipeline", "fewer inputs than the rig's and its external inputs");
  p->saturated = 0;
  p->pose_driven = false;
  const PipelineStatus st = run_stages(p, inputs, Stage::kSkinning, probe, report);
  report_input_flags(*p, report);
  return st;
}

PipelineStatus pipeline_step_locals(Pipeline* p, std::span<const skeleton::LocalPose> locals,
                                    std::span<const int32_t> external, const StepProbe* probe, StepReport* report) {
  begin_report(report);
  if (p == nullptr || p->rig == nullptr) return stage_fail(PipelineError::kArena, "pipeline", "not initialised");
  // The skinning stage: the pose from the locals, the DOFs measured from it.
  const uint64_t started = probe_now(probe);
  if (!engine::engine_step_locals(&p->engine, locals))
    return stage_fail(PipelineError::kBadInput, "skinning", "one local pose per joint is needed");
  p->pose_driven = true;
  p->saturated = 0;
  measure_dofs(p);
  const uint32_t rig_inputs = p->rig->input_count;
  for (uint32_t i = rig_inputs; i < p->input_count; ++i)
    p->measured[i] = i - rig_inputs < external.size() ? external[i - rig_inputs] : 0;
  stages::take_reference(p);
  stage_done(probe, report, Stage::kSkinning, started, *p);
  const PipelineStatus st = run_stages(p, p->measured, Stage::kSph, probe, report);
  p->pose_driven = false;
  report_input_flags(*p, report);
  return st;
}

}  // namespace sinew::pipeline
