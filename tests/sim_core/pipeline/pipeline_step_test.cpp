// pipeline_step's contract (sim_core/pipeline/pipeline.hpp): it times the
// stages that ran on the caller's clock, reports the per-input flags, and
// the first failing stage ends the tick.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "sim_core/pipeline/stage_table.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace {

namespace pl = sinew::pipeline;

pl::PipelineOptions step_test_options(std::initializer_list<pl::Stage> layers) {
  pl::PipelineOptions o;
  o.stages = pl::StageSet::none();
  for (pl::Stage s : layers) o.stages.set(s, true);
  return o;
}

// A clock that advances 7 ns per reading, and the stages seen after each ran.
struct StepTestProbe {
  uint64_t now = 1000;
  std::vector<pl::Stage> seen;
  pl::StepProbe probe() {
    pl::StepProbe p;
    p.now_ns = [](void* c) { return static_cast<StepTestProbe*>(c)->now += 7; };
    p.after_stage = [](void* c, pl::Stage s, const pl::Pipeline&) {
      static_cast<StepTestProbe*>(c)->seen.push_back(s);
    };
    p.context = this;
    return p;
  }
};

TEST(PipelineStep, TimesEveryStageThatRanOnTheCallersClock) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::string error;
  ASSERT_TRUE(arm->start(step_test_options({pl::Stage::kMetaballs, pl::Stage::kBarnet}), &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  StepTestProbe clock;
  const pl::StepProbe probe = clock.probe();
  pl::StepReport report;
  ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs, &probe, &report).ok());
  const std::vector<pl::Stage> ran = {pl::Stage::kSkinning, pl::Stage::kMetaballs, pl::Stage::kBarnet};
  EXPECT_EQ(clock.seen, ran);
  for (const pl::StageInfo& s : pl::kStages) {
    const bool expected =
        s.stage == pl::Stage::kSkinning || s.stage == pl::Stage::kMetaballs || s.stage == pl::Stage::kBarnet;
    EXPECT_EQ(report.ran.has(s.stage), expected) << s.name;
    // One reading before and one after each stage: 7 ns on this clock.
    EXPECT_EQ(report.stage_ns[static_cast<uint32_t>(s.stage)], expected ? 7u : 0u) << s.name;
  }
  // Without a probe nothing is timed, and the report is still written.
  ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs, nullptr, &report).ok());
  for (uint64_t ns : report.stage_ns) EXPECT_EQ(ns, 0u);
  EXPECT_TRUE(report.ran.has(pl::Stage::kBarnet));
}

// A layer that fails stops the tick: the stages after it do not run, and the
// status names it. The metaballs state is broken on purpose (not initialised).
TEST(PipelineStep, TheFirstFailingStageEndsTheTick) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::string error;
  ASSERT_TRUE(arm->start(step_test_options({pl::Stage::kMetaballs, pl::Stage::kBarnet, pl::Stage::kAnatomy}), &error))
      << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs).ok());
  arm->pipeline.metaballs.state.bone = {};
  StepTestProbe clock;
  const pl::StepProbe probe = clock.probe();
  pl::StepReport report;
  const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs, &probe, &report);
  EXPECT_EQ(st.error, pl::PipelineError::kLayer);
  EXPECT_NE(std::string(st.message).find("metaballs"), std::string::npos) << st.message;
  const std::vector<pl::Stage> ran = {pl::Stage::kSkinning, pl::Stage::kMetaballs};
  EXPECT_EQ(clock.seen, ran);
  EXPECT_FALSE(report.ran.has(pl::Stage::kBarnet));
  EXPECT_FALSE(report.ran.has(pl::Stage::kAnatomy));
}

// The inputs of the joint driven past a limit are flagged clamped (the flag
// is the joint's: every DOF of it); the other inputs are not.
TEST(PipelineStep, ReportsTheInputsWhoseJointWasClamped) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::string error;
  ASSERT_TRUE(arm->start(step_test_options({}), &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  std::vector<uint8_t> flags(arm->pipeline.input_count, 0xff);
  pl::StepReport report;
  report.input_flags = flags;
  ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs, nullptr, &report).ok());
  for (uint8_t f : flags) EXPECT_EQ(f, 0u);
  // The first joint with a DOF whose upper limit leaves room above it.
  const sinew::rig::JointRecord* clamped = nullptr;
  for (const sinew::rig::JointRecord& j : arm->rig.joints)
    if (j.dof_count > 0 && j.dof_max[0] < INT32_MAX - (1 << 26) && clamped == nullptr) {
      clamped = &j;
      inputs[j.first_input] = j.dof_max[0] + (1 << 26);  // about 5.6 degrees past it
    }
  ASSERT_NE(clamped, nullptr);
  ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs, nullptr, &report).ok());
  for (uint32_t i = 0; i < flags.size(); ++i) {
    const bool owned = i >= clamped->first_input && i < clamped->first_input + clamped->dof_count;
    EXPECT_EQ(flags[i], owned ? uint8_t{pl::kInputClamped} : uint8_t{0}) << "input " << i;
  }
}

// Every stage has a row, in order, and every option names a stage and a
// field; find_stage finds each name and nothing else.
TEST(StageTable, NamesEveryStageOnce) {
  for (uint32_t i = 0; i < pl::kStageCount; ++i) {
    const pl::StageInfo& s = pl::kStages[i];
    EXPECT_EQ(static_cast<uint32_t>(s.stage), i);
    EXPECT_EQ(pl::find_stage(s.name, std::string(s.name).size()), &s);
    EXPECT_STREQ(pl::stage_name(s.stage), s.name);
  }
  EXPECT_EQ(pl::find_stage("sphx", 4), nullptr);
  EXPECT_EQ(pl::find_stage("sp", 2), nullptr);
  for (const pl::StageOption& o : pl::kStageOptions) {
    EXPECT_NE(o.stage, pl::Stage::kSkinning) << o.key;
    EXPECT_TRUE(o.kind == pl::OptionKind::kNumber ? o.number != nullptr : o.flag != nullptr) << o.key;
  }
}

TEST(StageTable, DescribesTheLayersARigCarries) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  char text[512];
  pl::describe_layers(arm->rig, arm->layers, text, sizeof text);
  // Each layer the arm carries, by the table's name.
  for (const pl::StageInfo& s : pl::kStages) {
    if (s.stage != pl::Stage::kSkinning && s.compiled(arm->layers) > 0) {
      EXPECT_NE(std::string(text).find(s.name), std::string::npos) << text;
    }
  }
  pl::describe_layers(arm->rig, pl::LayerSet{}, text, sizeof text);
  EXPECT_STREQ(text, "none");
}

}  // namespace

namespace {

// pipeline_init runs each enabled stage's validate (its layers' own
// validators) before any init: a LayerSet assembled by hand, not by the
// loader, meets the same checks. The muscles' init does not validate, so
// without the stage's validate this model would be initialised.
TEST(PipelineInit, RunsTheStagesValidatorsOnAHandBuiltLayerSet) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  ASSERT_TRUE(arm->layers.anatomy.has_muscles);
  std::vector<sinew::muscle::MuscleRecord> muscles(arm->layers.anatomy.muscles.muscles.begin(),
                                                   arm->layers.anatomy.muscles.muscles.end());
  muscles[0].pivot_bone = static_cast<int32_t>(arm->rig.joint_count()) + 3;  // no such joint
  pl::LayerSet edited = arm->layers;
  edited.anatomy.muscles.muscles = muscles;
  const pl::PipelineOptions options = step_test_options({pl::Stage::kAnatomy});
  std::vector<uint64_t> memory(pl::pipeline_state_bytes(arm->rig, edited, options) / 8 + 1, 0);
  pl::Pipeline p;
  const pl::PipelineStatus st = pl::pipeline_init(arm->rig, edited, options, memory.data(), memory.size() * 8, &p);
  EXPECT_EQ(st.error, pl::PipelineError::kBadModel);
  EXPECT_EQ(std::string(st.message).rfind("anatomy: muscle[0].pivot_bone", 0), 0u) << st.message;
  // The same model with the layer off is not checked: it does not run.
  const pl::PipelineOptions off = step_test_options({});
  std::vector<uint64_t> memory_off(pl::pipeline_state_bytes(arm->rig, edited, off) / 8 + 1, 0);
  EXPECT_TRUE(pl::pipeline_init(arm->rig, edited, off, memory_off.data(), memory_off.size() * 8, &p).ok());
}

// A layer built for another rig must not reach the step: the stage validators
// compare the model's joint, input and vertex counts with the rig's (the
// loader did this once in its own code, so a hand-built set skipped it).
TEST(PipelineInit, RefusesALayerBuiltForAnotherRig) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  ASSERT_TRUE(arm->layers.metaballs.present);
  ASSERT_GT(arm->layers.barnet.count, 0u);
  struct Case {
    pl::Stage stage;
    void (*edit)(pl::LayerSet*);
    const char* message;
  };
  const Case cases[] = {
      {pl::Stage::kMetaballs, [](pl::LayerSet* l) { l->metaballs.model.joint_count += 1; }, "metaballs: joint_count"},
      {pl::Stage::kMetaballs, [](pl::LayerSet* l) { l->metaballs.model.vertex_count -= 1; }, "metaballs: vertex_count"},
      {pl::Stage::kBarnet, [](pl::LayerSet* l) { l->barnet.net[0].joint_count += 1; }, "barnet[0]: joint_count"},
      {pl::Stage::kBarnet, [](pl::LayerSet* l) { l->barnet.net[0].input_count += 1; }, "barnet[0]: input_count"},
      {pl::Stage::kBarnet, [](pl::LayerSet* l) { l->barnet.net[0].vertex_count += 1; }, "barnet[0]: vertex_count"},
      {pl::Stage::kBarnet, [](pl::LayerSet* l) { l->barnet.net[0].external_count = l->external_count() + 1; },
       "barnet[0]: external_count"},
  };
  for (const Case& c : cases) {
    pl::LayerSet edited = arm->layers;
    c.edit(&edited);
    const pl::PipelineOptions options = step_test_options({c.stage});
    std::vector<uint64_t> memory(pl::pipeline_state_bytes(arm->rig, edited, options) / 8 + 1, 0);
    pl::Pipeline p;
    const pl::PipelineStatus st = pl::pipeline_init(arm->rig, edited, options, memory.data(), memory.size() * 8, &p);
    EXPECT_EQ(st.error, pl::PipelineError::kBadModel) << c.message;
    EXPECT_NE(std::string(st.message).find(c.message), std::string::npos) << st.message;
  }
}

}  // namespace
