// The bar-net stage's rig sections: every BNET section, one net each, loaded
// into the layer set (sim_core/barnet/barnet_section.hpp describes the
// record).
#include "sim_core/barnet/barnet_validate.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {
namespace {

using rig::LoadError;
using rig::LoadStatus;

constexpr auto barnet_array = [](std::string_view n) { return layer::array_ref(barnet::kBarnetSectionArrays, n); };

LoadStatus load_net(const SectionView& v, const rig::Rig& rig, uint32_t external_count, barnet::BarnetModel* out) {
  const barnet::BarnetSectionParams p = params_of<barnet::BarnetSectionParams>(v);
  const bool v2 = v.header.layer_version == barnet::kBarnetSectionVersion2;
  *out = {p.joint_count,
          p.input_count,
          p.vertex_count,
          named<fx::Mat34, barnet_array("inverse_bind")>(v),
          named<barnet::NodeRecord, barnet_array("nodes")>(v),
          named<barnet::BarRecord, barnet_array("bars")>(v),
          named<barnet::LoadRecord, barnet_array("loads")>(v),
          named<barnet::ControlTriangle, barnet_array("triangles")>(v),
          named<barnet::WrapRecord, barnet_array("wrap")>(v),
          0,
          {}};
  if (v2) {
    if (p.external_count != external_count)
      return section_fail(LoadError::kBadValue, v, "external_count", -1,
                          "differs from the rig's external inputs (EXTI)", p.external_count, true);
    out->external_count = p.external_count;
    out->q_inputs = named<barnet::ForceDensityInput, barnet_array("q_inputs")>(v);
  }
  const barnet::LayerStatus st = barnet::barnet_validate(*out, rig);
  if (!st.ok()) return section_layer_fail(LoadError::kBadValue, v, st.message);
  return {};
}

}  // namespace

LoadStatus barnet_load(std::span<const SectionView> sections, const rig::Rig& rig, LayerSet* set) {
  for (const SectionView& v : sections) {
    if (v.id != barnet::kSectionBarnet) continue;
    LoadStatus st = load_net(v, rig, set->external_count(), &set->barnet.net[set->barnet.count++]);
    if (!st.ok()) return st;
  }
  return {};
}

}  // namespace sinew::pipeline::stages
