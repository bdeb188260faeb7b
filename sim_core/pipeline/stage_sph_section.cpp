// The SPH stage's rig sections: every SPHJ section, one SPH elastic joint
// each, loaded into the layer set (sim_core/sph/sph_section.hpp describes
// the record).
#include "sim_core/sph/sph_model.hpp"
#include "stage_fns.hpp"
#include "stage_sph_rate.hpp"

namespace sinew::pipeline::stages {
namespace {

using rig::LoadError;
using rig::LoadStatus;

constexpr auto sph_array = [](std::string_view n) { return layer::array_ref(sph::kSphSectionArrays, n); };

LoadStatus load_joint(const SectionView& v, const rig::Rig& rig, uint32_t external_count, SphJointLayer* out) {
  // Version 1 has no surface tension: its record stops before tension_gain.
  sph::SphSectionParams p{};
  if (v.header.layer_version == sph::kSphSectionVersion2) {
    p = params_of<sph::SphSectionParams>(v);
  } else {
    const sph::SphSectionParamsV1 p1 = params_of<sph::SphSectionParamsV1>(v);
    std::memcpy(static_cast<void*>(&p.params), p1.params, sizeof p1.params);
    p.params.tension_gain = 0;
    p.joint = p1.joint;
    p.force_input = p1.force_input;
  }
  sph::SphModel& m = out->model;
  m.params = p.params;
  m.joint = p.joint;
  m.rest_local[0] = named<fx::Len, sph_array("rest_local_x")>(v);
  m.rest_local[1] = named<fx::Len, sph_array("rest_local_y")>(v);
  m.rest_local[2] = named<fx::Len, sph_array("rest_local_z")>(v);
  m.rest_model[0] = named<fx::Len, sph_array("rest_model_x")>(v);
  m.rest_model[1] = named<fx::Len, sph_array("rest_model_y")>(v);
  m.rest_model[2] = named<fx::Len, sph_array("rest_model_z")>(v);
  m.skin_rest[0] = named<fx::Len, sph_array("skin_rest_x")>(v);
  m.skin_rest[1] = named<fx::Len, sph_array("skin_rest_y")>(v);
  m.skin_rest[2] = named<fx::Len, sph_array("skin_rest_z")>(v);
  m.bone = named<uint8_t, sph_array("bone")>(v);
  m.skin_vertex = named<uint32_t, sph_array("skin_vertex")>(v);
  if (v.header.rate_hz == 0)
    return section_fail(LoadError::kBadValue, v, "rate_hz", -1, "an SPH joint's gains need its tick rate");
  const sph::LayerStatus st = sph::sph_validate(m, rig);
  if (!st.ok()) return section_layer_fail(LoadError::kBadValue, v, st.message);
  if (rig.joints[m.joint.distal_joint].dof_count == 0 ||
      rig.joints[m.joint.distal_joint].dof_kind != static_cast<uint8_t>(rig::DofKind::kRotation))
    return section_fail(LoadError::kBadValue, v, "distal_joint", -1, "the driven joint needs a rotational DOF to bend",
                        m.joint.distal_joint, true);
  if (p.force_input != kNoExternalInput && p.force_input >= external_count)
    return section_fail(LoadError::kBadIndex, v, "force_input", -1, "names no external input", p.force_input, true);
  out->force_input = p.force_input;
  return {};
}

}  // namespace

LoadStatus sph_load(std::span<const SectionView> sections, const rig::Rig& rig, LayerSet* set) {
  for (const SectionView& v : sections) {
    if (v.id != sph::kSectionSphJoint) continue;
    LoadStatus st = load_joint(v, rig, set->external_count(), &set->sph.joint[set->sph.count]);
    if (!st.ok()) return st;
    // The joints' gains are built for one tick rate (sph_gains_for_rate
    // rescales them all from it).
    if (set->rate_hz != 0 && set->rate_hz != v.header.rate_hz)
      return section_fail(LoadError::kBadValue, v, "rate_hz", -1, "differs from another SPH joint's", v.header.rate_hz,
                          true);
    set->rate_hz = v.header.rate_hz;
    ++set->sph.count;
  }
  return {};
}

}  // namespace sinew::pipeline::stages
