// What the SPH stage keeps (sph-elastic-joints-tresca; docs/sph.md): the
// rig's SPH joints, up to kMaxSphJoints, each with its optional force input.
#pragma once

#include <cstdint>

#include "layer_format.hpp"
#include "sim_core/sph/sph_section.hpp"
#include "sim_core/sph/sph_state.hpp"
#include "stage.hpp"

namespace sinew::pipeline {

using sph::kMaxSphJoints;

struct SphJointLayer {
  sph::SphModel model;
  uint32_t force_input = kNoExternalInput;  // index into external, or kNoExternalInput
};

struct SphLayers {
  SphJointLayer joint[kMaxSphJoints];
  uint32_t count = 0;
};

struct SphRun {
  sph::SphModel model[kMaxSphJoints];  // the joints' models, gains converted for the loop's rate
  sph::SphState joint[kMaxSphJoints];  // each keeps a pointer to its model[]
  uint32_t count = 0;                  // joints running (0 when switched off)
  bool started = false;                // the first step resets the particles into its pose
};

// Its run-time options ([layers] tresca, sph_joint,
// sph_measured_from_sources; the stage table's option rows).
struct SphOptions {
  bool tresca = true;  // the yield condition, eqs. (3)-(4)
  // The joints' angles are measured (a wearable's sensors), hence already
  // the truth under the load: the particles move the soft tissue only and do
  // not bend the joint again (sph::SphInputs::joint_measured; docs/sph.md,
  // "Measured and simulated joints"). false: the joints are simulated.
  bool joint_measured = false;
  // With joint_measured false: a joint whose driven DOF a source measures
  // (pipeline_set_measured_inputs) runs measured all the same, a glove's
  // elbow sensor being the truth under load. false: every joint is
  // simulated whatever its sources (a robot whose joint inputs are commanded
  // targets, the deflection under load being what the particles add).
  bool measured_from_sources = true;
};

// Its options' fields in PipelineOptions (stage_sph.cpp).
bool* sph_tresca_option(PipelineOptions* o);
bool* sph_joint_measured_option(PipelineOptions* o);
bool* sph_measured_from_sources_option(PipelineOptions* o);

template <>
struct StageData<Stage::kSph> {
  using Layers = SphLayers;
  using Run = SphRun;
  using Options = SphOptions;
  static constexpr std::array<const layer::SectionDescriptor*, 1> sections = {&sph::kSphSection};
  static constexpr std::array<StageOption, 3> options = {
      StageOption{"tresca",
                  Stage::kSph,
                  OptionKind::kFlag,
                  sph_tresca_option,
                  {nullptr, nullptr},
                  nullptr,
                  0,
                  0,
                  "tresca",
                  true,
                  "the SPH joints' Tresca yield condition, eqs. (3)-(4) (docs/sph.md)"},
      StageOption{"sph_joint",
                  Stage::kSph,
                  OptionKind::kChoice,
                  sph_joint_measured_option,
                  {"simulated", "measured"},
                  nullptr,
                  0,
                  0,
                  "sph_joint_measured",
                  false,
                  "\"measured\": the sensors' angles are the truth under load, the particles only move the tissue "
                  "(docs/sph.md)"},
      StageOption{"sph_measured_from_sources",
                  Stage::kSph,
                  OptionKind::kFlag,
                  sph_measured_from_sources_option,
                  {nullptr, nullptr},
                  nullptr,
                  0,
                  0,
                  "sph_measured_from_sources",
                  false,
                  "an SPH joint whose driven DOF a source measures runs measured; false: simulated whatever its "
                  "sources (docs/sph.md)"},
  };
  static constexpr bool parallel = true;  // the neighbour search by slabs and the per-particle loops over the workers
};

}  // namespace sinew::pipeline
