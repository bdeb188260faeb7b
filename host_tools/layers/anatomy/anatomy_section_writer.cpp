#include "anatomy_section_writer.hpp"

#include <cstring>

#include "host_tools/layers/sections/section_builder.hpp"
#include "sim_core/muscle/muscle_shape.hpp"
#include "sim_core/muscle/primitive_deform.hpp"

namespace sinew::layers {

LayerSection muscles_section(const ::sinew::muscle::MuscleModel& m) {
  // Version 1 while no primitive is deformed (those rigs keep their bytes).
  bool deformed = false;
  for (const auto& d : m.deformations) deformed = deformed || ::sinew::muscle::is_deformed(d);
  // Version 3 only while some muscle has a non-default shape.
  bool shaped = false;
  for (const auto& s : m.shapes) shaped = shaped || !::sinew::muscle::is_default_shape(s);
  // Version 4 only while some primitive is a general superquadric.
  bool general = false;
  for (const auto& r : m.primitives) general = general || (!m.exponents.empty() && r.exponent == 0);
  const ::sinew::muscle::MusclesSectionParams p{m.joint_count, m.ring_vertices};
  const uint32_t version = general    ? ::sinew::muscle::kMusclesSectionVersion4
                           : shaped   ? ::sinew::muscle::kMusclesSectionVersion3
                           : deformed ? ::sinew::muscle::kMusclesSectionVersion2
                                      : pipeline::kLayerSectionVersion;
  SectionBuilder b = section_builder(muscle::kMusclesSection, version, 0, p);
  b.array("muscles", m.muscles).array("primitives", m.primitives);
  if (general || shaped || deformed)
    b.array("deformations", deformed ? m.deformations : std::span<const ::sinew::muscle::PrimitiveDeformation>{});
  if (general || shaped) b.array("shapes", shaped ? m.shapes : std::span<const ::sinew::muscle::MuscleShape>{});
  if (general) b.array("exponents", m.exponents);
  return b.finish();
}

LayerSection skin_section(const ::sinew::elastic_skin::SkinModel& m, std::span<const uint32_t> region,
                          std::span<const fx::Unit> region_weight, const uint32_t (&base_acceleration)[3]) {
  // Version 1 while the solver record is the default (the bytes of rigs
  // without the new settings do not change); version 2 otherwise.
  // Version 3 only with edge dashpots (the record's last member), 4 with
  // the fat along the surface normal, 5 with base-acceleration inputs, 6
  // with LEMAN's relaxation integrator (SkinSurfaceParams not the default).
  // Every version has the same arrays.
  auto with_skin_arrays = [&](SectionBuilder& b) {
    b.array("anchors", m.anchors)
        .array("anchor_stiffness", m.anchor_stiffness)
        .array("fat", m.fat)
        .array("edges", m.edges)
        .array("bands", m.bands);
    b.array("region_vertex", region).array("region_weight", region_weight);
    return b.finish();
  };
  const elastic_skin::SkinSolverParams defaults{};
  const bool v5 = base_acceleration[0] != pipeline::kNoExternalInput ||
                  base_acceleration[1] != pipeline::kNoExternalInput ||
                  base_acceleration[2] != pipeline::kNoExternalInput;
  const elastic_skin::SkinSurfaceParams surface_defaults{};
  const bool v6 = std::memcmp(&m.surface, &surface_defaults, sizeof surface_defaults) != 0;
  if (v5 || v6) {
    ::sinew::elastic_skin::SkinSectionParamsV6 p6{};
    ::sinew::elastic_skin::SkinSectionParamsV5& p5 = p6.v5;
    p5.v3 = {m.joint_count, m.vertex_count, m.params, m.solver};
    for (int c = 0; c < 3; ++c) p5.base_acceleration_input[c] = base_acceleration[c];
    p6.surface = m.surface;
    if (v6) {
      SectionBuilder b =
          section_builder(elastic_skin::kSkinSection, ::sinew::elastic_skin::kSkinSectionVersion6, 0, p6);
      return with_skin_arrays(b);
    }
    SectionBuilder b = section_builder(elastic_skin::kSkinSection, ::sinew::elastic_skin::kSkinSectionVersion5, 0, p5);
    return with_skin_arrays(b);
  }
  const bool v4 = m.solver.fat_normal != 0;
  const bool v3 = !v4 && m.solver.edge_damping != 0;
  const bool v2 = !v4 && !v3 && std::memcmp(&m.solver, &defaults, ::sinew::elastic_skin::kSkinSolverBytesV2) != 0;
  ::sinew::elastic_skin::SkinSectionParamsV3 p{};
  p.joint_count = m.joint_count;
  p.vertex_count = m.vertex_count;
  p.params = m.params;
  p.solver = m.solver;
  // The version 1 and 2 records are prefixes of the version 3 one.
  const uint32_t size = v4 || v3 ? uint32_t{sizeof(::sinew::elastic_skin::SkinSectionParamsV3)}
                        : v2     ? uint32_t{sizeof(::sinew::elastic_skin::SkinSectionParamsV2)}
                                 : uint32_t{sizeof(::sinew::elastic_skin::SkinSectionParams)};
  const uint32_t version = v4   ? ::sinew::elastic_skin::kSkinSectionVersion4
                           : v3 ? ::sinew::elastic_skin::kSkinSectionVersion3
                           : v2 ? ::sinew::elastic_skin::kSkinSectionVersion2
                                : pipeline::kLayerSectionVersion;
  SectionBuilder b(elastic_skin::kSkinSection, version, 0, &p, size);
  return with_skin_arrays(b);
}

}  // namespace sinew::layers
