#include "barnet_section_writer.hpp"

#include <cstring>

#include "host_tools/layers/sections/section_builder.hpp"

namespace sinew::layers {

LayerSection barnet_section(const ::sinew::barnet::BarnetModel& m) {
  // Version 1 while no load reads an external input and no q follows one
  // (the bytes of rigs without them do not change); version 2 otherwise.
  bool v2 = !m.q_inputs.empty();
  for (const ::sinew::barnet::LoadRecord& l : m.loads) v2 = v2 || l.input >= m.input_count;
  const ::sinew::barnet::BarnetSectionParams p{m.joint_count, m.input_count, m.vertex_count, v2 ? m.external_count : 0};
  SectionBuilder b = section_builder(
      barnet::kBarnetSection, v2 ? ::sinew::barnet::kBarnetSectionVersion2 : pipeline::kLayerSectionVersion, 0, p);
  b.array("inverse_bind", m.inverse_bind)
      .array("nodes", m.nodes)
      .array("bars", m.bars)
      .array("loads", m.loads)
      .array("triangles", m.triangles)
      .array("wrap", m.wrap);
  if (v2) b.array("q_inputs", m.q_inputs);
  return b.finish();
}

}  // namespace sinew::layers
