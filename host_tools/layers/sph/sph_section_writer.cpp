#include "sph_section_writer.hpp"

#include <cstring>

#include "host_tools/layers/sections/section_builder.hpp"

namespace sinew::layers {

LayerSection sph_section(const sph::SphModel& m, uint32_t rate_hz, uint32_t force_input) {
  // Version 1 without surface tension (the bytes of rigs without it do not
  // change); version 2 stores the whole SphParams.
  ::sinew::sph::SphSectionParams p2{};
  ::sinew::sph::SphSectionParamsV1 p1{};
  const bool v2 = m.params.tension_gain != 0;
  p2.params = m.params;
  p2.joint = p1.joint = m.joint;
  p2.force_input = p1.force_input = force_input;
  std::memcpy(p1.params, &m.params, sizeof p1.params);
  SectionBuilder b = v2 ? section_builder(sph::kSphSection, ::sinew::sph::kSphSectionVersion2, rate_hz, p2)
                        : section_builder(sph::kSphSection, pipeline::kLayerSectionVersion, rate_hz, p1);
  b.array("rest_local_x", m.rest_local[0])
      .array("rest_local_y", m.rest_local[1])
      .array("rest_local_z", m.rest_local[2]);
  b.array("rest_model_x", m.rest_model[0])
      .array("rest_model_y", m.rest_model[1])
      .array("rest_model_z", m.rest_model[2]);
  b.array("bone", m.bone).array("skin_vertex", m.skin_vertex);
  b.array("skin_rest_x", m.skin_rest[0]).array("skin_rest_y", m.skin_rest[1]).array("skin_rest_z", m.skin_rest[2]);
  return b.finish();
}

}  // namespace sinew::layers
