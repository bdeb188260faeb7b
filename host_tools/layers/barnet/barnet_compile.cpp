#include "barnet_compile.hpp"

#include "host_tools/layers/barnet/barnet_section_writer.hpp"
#include "host_tools/layers/barnet/joint_net.hpp"
#include "host_tools/layers/barnet/muscle_net.hpp"
#include "host_tools/layers/barnet/wrinkle_net.hpp"
#include "sim_core/barnet/barnet_section.hpp"

namespace sinew::layers {
namespace {

// The volume-keeping push's outcome, for the report: a step no push in
// reach restores (the bend folds the tube) holds the previous push.
std::string volume_note(const barnet::NetSpec& net) {
  if (net.volume_steps == 0) return "";
  std::string note = "; the push keeps the tube's volume at " +
                     std::to_string(net.volume_steps - net.volume_short_steps) + " of " +
                     std::to_string(net.volume_steps) + " scheduled bends";
  if (net.volume_short_steps != 0)
    note += " (" + std::to_string(net.volume_short_steps) + " beyond any push in reach hold the previous one)";
  return note;
}

}  // namespace

void HostLayer<pipeline::Stage::kBarnet>::bent_joints(const Tables& tables, std::vector<const JointRef*>* joints) {
  for (const BarnetTable& t : tables) joints->push_back(&t.joint);
}

bool HostLayer<pipeline::Stage::kBarnet>::declare_inputs(const rigc::RigSpec&, const Tables& tables,
                                                         std::vector<ExternalInputTable>* external, std::string*) {
  for (const BarnetTable& t : tables) {
    declare_input(external, {t.force_input, "N", "force", -40, 40, t.joint.where});
    declare_input(external, {t.q_input, "", "scalar", 1.0 / 256, 256, t.joint.where});
  }
  return true;
}

bool HostLayer<pipeline::Stage::kBarnet>::compile(const LayerCompile& c, const Tables& tables, std::string* error) {
  const rigc::RigSpec& spec = c.spec;
  if (tables.size() > sinew::barnet::kMaxBarnets) return layer_fail("[[barnet]]", "at most 8 bar-nets", error);
  for (size_t i = 0; i < tables.size(); ++i) {
    const BarnetTable& t = tables[i];
    const int j = resolve_joint(spec, t.joint, error);
    if (j < 0) return false;
    barnet::JointNetOptions o;
    o.segments = t.segments;
    o.rings = t.rings;
    o.ring_step = t.ring_step;
    o.force = t.force;
    o.external_count = static_cast<uint32_t>(c.inputs.size());
    if (const uint32_t k = c.input_index(t.force_input); k != pipeline::kNoExternalInput)
      o.force_input = static_cast<int>(k);
    if (const uint32_t k = c.input_index(t.q_input); k != pipeline::kNoExternalInput) o.q_input = static_cast<int>(k);
    o.force_input_hi = t.force_input_full;
    barnet::NetSpec net;
    barnet::BarnetBuild built;
    bool built_net = false;
    if (t.net == "joint") {
      built_net = barnet::joint_net(spec, c.geometry, j, o, &net, error);
    } else {
      barnet::JointMuscleNetOptions muscles;
      muscles.segments = t.segments;
      muscles.force = t.force;
      barnet::SkinWrinkleOptions wrinkles;
      wrinkles.force = t.force;
      built_net = t.net == "muscles"       ? barnet::joint_muscle_net(spec, c.geometry, j, muscles, &net, error)
                  : t.net == "wrinkles"    ? barnet::skin_wrinkle_net(spec, c.geometry, j, wrinkles, &net, error)
                  : t.net == "arm-muscles" ? barnet::arm_muscle_net(spec, {}, &net, error)
                                           : barnet::arm_wrinkle_net(spec, {}, &net, error);
      barnet::drive_from_inputs({o.external_count, o.force_input, o.force_input_lo, o.force_input_hi, o.q_input}, &net);
    }
    if (!built_net || !barnet::build_barnet(net, spec, &built, error)) return layer_fail(t.joint.where, *error, error);
    c.sections->push_back(barnet_section(built.model()));
    c.report->push_back("barnet[" + std::to_string(i) + "] " + spec.joints[static_cast<size_t>(j)].name + ": " +
                        std::to_string(built.nodes.size()) + " nodes, " + std::to_string(built.bars.size()) +
                        " bars, " + std::to_string(built.loads.size()) + " loads, " +
                        std::to_string(built.wrap.size()) + " wrapped vertices" + volume_note(net));
  }
  return true;
}

}  // namespace sinew::layers
