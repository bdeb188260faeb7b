// The anatomy stage's rig sections: MUSC (every muscle and primitive) and
// SKIN (the elastic skin, which needs MUSC), at most one each, loaded into
// the layer set (sim_core/muscle/muscle_section.hpp and
// sim_core/elastic_skin/skin_section.hpp describe the records).
#include "sim_core/elastic_skin/skin_validate.hpp"
#include "sim_core/muscle/muscle_validate.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {
namespace {

using rig::LoadError;
using rig::LoadStatus;

constexpr auto muscle_array = [](std::string_view n) { return layer::array_ref(muscle::kMusclesSectionArrays, n); };
constexpr auto skin_array = [](std::string_view n) { return layer::array_ref(elastic_skin::kSkinSectionArrays, n); };

LoadStatus load_muscles(const SectionView& v, const rig::Rig& rig, muscle::MuscleModel* out) {
  const muscle::MusclesSectionParams p = params_of<muscle::MusclesSectionParams>(v);
  const bool v2 = v.header.layer_version >= muscle::kMusclesSectionVersion2;
  const bool v3 = v.header.layer_version >= muscle::kMusclesSectionVersion3;
  const bool v4 = v.header.layer_version == muscle::kMusclesSectionVersion4;
  *out = {p.joint_count,
          p.ring_vertices,
          named<muscle::MuscleRecord, muscle_array("muscles")>(v),
          named<muscle::PrimitiveRecord, muscle_array("primitives")>(v),
          v2 ? named<muscle::PrimitiveDeformation, muscle_array("deformations")>(v)
             : std::span<const muscle::PrimitiveDeformation>{},
          v3 ? named<muscle::MuscleShape, muscle_array("shapes")>(v) : std::span<const muscle::MuscleShape>{},
          v4 ? named<muscle::PrimitiveExponents, muscle_array("exponents")>(v)
             : std::span<const muscle::PrimitiveExponents>{}};
  const muscle::LayerStatus st = muscle::muscle_validate(*out, rig);
  if (!st.ok()) return section_layer_fail(LoadError::kBadValue, v, st.message);
  return {};
}

// The skin's params record, from any version: older ones get the fields
// they lack at their defaults.
LoadStatus skin_params(const SectionView& v, std::span<const ExternalInputRecord> external, LayerSet* set,
                       elastic_skin::SkinSectionParamsV3* out, elastic_skin::SkinSurfaceParams* surface) {
  elastic_skin::SkinSectionParamsV3& p = *out;
  *surface = {};
  if (v.header.layer_version == elastic_skin::kSkinSectionVersion5 ||
      v.header.layer_version == elastic_skin::kSkinSectionVersion6) {
    const elastic_skin::SkinSectionParamsV5 p5 = v.header.layer_version == elastic_skin::kSkinSectionVersion6
                                                     ? params_of<elastic_skin::SkinSectionParamsV6>(v).v5
                                                     : params_of<elastic_skin::SkinSectionParamsV5>(v);
    if (v.header.layer_version == elastic_skin::kSkinSectionVersion6)
      *surface = params_of<elastic_skin::SkinSectionParamsV6>(v).surface;
    p = p5.v3;
    for (int c = 0; c < 3; ++c) {
      const uint32_t k = p5.base_acceleration_input[c];
      if (k != kNoExternalInput && k >= external.size())
        return section_fail(LoadError::kBadIndex, v, "base_acceleration_input", c,
                            "not an external input of the rig (EXTI)", k, true);
      if (k != kNoExternalInput && external[k].quantity != static_cast<uint32_t>(InputQuantity::kAcceleration))
        return section_fail(LoadError::kBadValue, v, "base_acceleration_input", c,
                            "names an external input that is not an acceleration", k, true);
      set->anatomy.skin_base_acceleration[c] = k;
    }
  } else if (v.header.layer_version == elastic_skin::kSkinSectionVersion3 ||
             v.header.layer_version == elastic_skin::kSkinSectionVersion4) {
    p = params_of<elastic_skin::SkinSectionParamsV3>(v);
  } else if (v.header.layer_version == elastic_skin::kSkinSectionVersion2) {  // the solver record without edge_damping
    const elastic_skin::SkinSectionParamsV2 p2 = params_of<elastic_skin::SkinSectionParamsV2>(v);
    p.joint_count = p2.joint_count;
    p.vertex_count = p2.vertex_count;
    p.params = p2.params;
    std::memcpy(static_cast<void*>(&p.solver), p2.solver, elastic_skin::kSkinSolverBytesV2);
  } else {  // version 1: the default solver (static relaxation)
    const elastic_skin::SkinSectionParams p1 = params_of<elastic_skin::SkinSectionParams>(v);
    p.joint_count = p1.joint_count;
    p.vertex_count = p1.vertex_count;
    p.params = p1.params;
  }
  return {};
}

LoadStatus load_skin(const SectionView& v, const rig::Rig& rig, LayerSet* set) {
  elastic_skin::SkinSectionParamsV3 p{};
  elastic_skin::SkinSurfaceParams surface{};
  LoadStatus ps = skin_params(v, set->external, set, &p, &surface);
  if (!ps.ok()) return ps;
  elastic_skin::SkinModel* out = &set->anatomy.skin;
  std::span<const uint32_t>* region = &set->anatomy.skin_region;
  std::span<const fx::Unit>* region_weight = &set->anatomy.skin_region_weight;
  *out = {p.joint_count,
          p.vertex_count,
          named<elastic_skin::Anchor, skin_array("anchors")>(v),
          named<elastic_skin::Stiffness, skin_array("anchor_stiffness")>(v),
          named<fx::Len, skin_array("fat")>(v),
          named<elastic_skin::Edge, skin_array("edges")>(v),
          named<elastic_skin::RubberBand, skin_array("bands")>(v),
          p.params,
          p.solver,
          rig.triangles,
          surface};
  // fat_normal is a version 4 field (kept in 5): older sections keep the
  // anchor normal whatever their reserved byte holds.
  if (v.header.layer_version < elastic_skin::kSkinSectionVersion4) out->solver.fat_normal = 0;
  *region = named<uint32_t, skin_array("region_vertex")>(v);
  *region_weight = named<fx::Unit, skin_array("region_weight")>(v);
  out->region = *region;  // the static relaxation moves the region and its halo (checked below)
  if (out->vertex_count != rig.vertex_count())
    return section_fail(LoadError::kBadValue, v, "vertex_count", -1, "differs from the rig's", out->vertex_count, true);
  if (region->size() != region_weight->size())
    return section_fail(LoadError::kSectionSize, v, "region_weight", -1, "count differs from region_vertex",
                        static_cast<int64_t>(region_weight->size()), true);
  for (uint32_t i = 0; i < region->size(); ++i) {
    if ((*region)[i] >= rig.vertex_count() || (i > 0 && (*region)[i] <= (*region)[i - 1]))
      return section_fail(LoadError::kBadIndex, v, "region_vertex", i, "not an ascending vertex index of the rig",
                          (*region)[i], true);
    if ((*region_weight)[i] <= 0 || (*region_weight)[i] > fx::kUnitOne)
      return section_fail(LoadError::kBadValue, v, "region_weight", i, "outside (0, 1]", (*region_weight)[i], true);
  }
  const muscle::LayerStatus st = elastic_skin::skin_validate(*out, rig, set->anatomy.muscles);
  if (!st.ok()) return section_layer_fail(LoadError::kBadValue, v, st.message);
  return {};
}

}  // namespace

// The muscles first: the skin rides on them.
LoadStatus anatomy_load(std::span<const SectionView> sections, const rig::Rig& rig, LayerSet* set) {
  for (const SectionView& v : sections) {
    if (v.id != muscle::kSectionMuscles) continue;
    set->anatomy.has_muscles = true;
    LoadStatus st = load_muscles(v, rig, &set->anatomy.muscles);
    if (!st.ok()) return st;
  }
  for (const SectionView& v : sections) {
    if (v.id != elastic_skin::kSectionElasticSkin) continue;  // layers_validate saw MUSC (the descriptor's needs)
    set->anatomy.has_skin = true;
    LoadStatus st = load_skin(v, rig, set);
    if (!st.ok()) return st;
  }
  return {};
}

}  // namespace sinew::pipeline::stages
