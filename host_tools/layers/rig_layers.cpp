#include "rig_layers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/layers/sections/layer_writer.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::layers {
namespace {

bool quantity_of(const std::string& name, pipeline::InputQuantity* out) {
  if (name == "force") return *out = pipeline::InputQuantity::kForce, true;
  if (name == "length") return *out = pipeline::InputQuantity::kLength, true;
  if (name == "angle") return *out = pipeline::InputQuantity::kAngle, true;
  if (name == "scalar") return *out = pipeline::InputQuantity::kScalar, true;
  if (name == "acceleration") return *out = pipeline::InputQuantity::kAcceleration, true;
  return false;
}

int32_t q16(double v) {
  const double s = std::floor(v * 65536.0 + 0.5);
  return static_cast<int32_t>(std::clamp(s, -2147483648.0, 2147483647.0));
}

}  // namespace

bool LayerSpecs::empty() const {
  bool none = external.empty();
#define SINEW_LAYER_SPEC_EMPTY(name, enumerator, sections, doc) none = none && name.empty();
  SINEW_STAGE_LIST(SINEW_LAYER_SPEC_EMPTY)
#undef SINEW_LAYER_SPEC_EMPTY
  return none;
}

bool add_layer_dofs(rigc::RigSpec* spec, const LayerSpecs& layers, std::vector<std::string>* report,
                    std::string* error) {
  std::vector<const JointRef*> refs;
#define SINEW_BENT_JOINTS(name, enumerator, sections, doc) \
  HostLayer<pipeline::Stage::enumerator>::bent_joints(layers.name, &refs);
  SINEW_STAGE_LIST(SINEW_BENT_JOINTS)
#undef SINEW_BENT_JOINTS
  if (refs.empty()) return true;
  RigGeometry g;
  if (!rig_geometry(*spec, &g, error)) return false;
  for (const JointRef* ref : refs) {
    const int j = resolve_joint(*spec, *ref, error);
    if (j < 0) return false;
    rigc::JointSpec& js = spec->joints[static_cast<size_t>(j)];
    if (!js.dofs.empty()) continue;
    const int parent = anatomical_parent(*spec, g, j);
    if (parent < 0)
      return layer_fail(ref->where, "joint '" + js.name + "' is a root: a layer bends the joint between two bones",
                        error);
    const Vec3d up = g.bone_dir[static_cast<size_t>(parent)], uj = g.bone_dir[static_cast<size_t>(j)];
    Vec3d axis = cross(up, uj);
    if (!(norm(axis) > 0.1)) axis = perpendicular(up);
    const Vec3d local = dir_to_local(g.frame[static_cast<size_t>(j)], normalized(axis));
    js.dof_kind = rigc::DofKind::kRotation;
    js.dofs.push_back({local, -150, 150});
    report->push_back("joint '" + js.name + "' gets one rotational DOF about its bend axis (" +
                      report_number(local[0]) + ", " + report_number(local[1]) + ", " + report_number(local[2]) +
                      ") in its frame, +-150 degrees");
  }
  return true;
}

bool compile_layers(const rigc::RigSpec& spec, const LayerSpecs& layers, std::vector<uint8_t>* blob,
                    std::vector<std::string>* report, std::string* error) {
  if (layers.empty()) return true;
  if (layers.rate_hz < 13 || layers.rate_hz > 100000)
    return layer_fail("[rig] rate_hz", "must be 13..100000 (a rate-dependent layer's substeps cover at most 80 ms)",
                      error);
  RigGeometry g;
  if (!rig_geometry(spec, &g, error)) return false;
  // The compiled core, loaded as the board will: a layer's builder may work
  // from it, and every layer is checked against it.
  std::vector<uint64_t> core(blob->size() / 8 + 1);
  std::memcpy(core.data(), blob->data(), blob->size());
  const auto* core_bytes = reinterpret_cast<const uint8_t*>(core.data());
  size_t arena_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(core_bytes, blob->size(), &arena_bytes);
  std::vector<uint64_t> arena(arena_bytes / 8 + 1);
  rig::Rig rig;
  if (st.ok()) st = rig::rig_init(core_bytes, blob->size(), arena.data(), arena.size() * 8, &rig);
  if (!st.ok()) return layer_fail("", std::string("internal: core blob rejected: ") + st.message, error);

  std::vector<LayerSection> sections;
  // External inputs: the declared ones, then those the layers read and the
  // spec does not declare, in stage order.
  std::vector<ExternalInputTable> external = layers.external;
#define SINEW_DECLARE_INPUTS(name, enumerator, sections, doc) \
  if (!HostLayer<pipeline::Stage::enumerator>::declare_inputs(spec, layers.name, &external, error)) return false;
  SINEW_STAGE_LIST(SINEW_DECLARE_INPUTS)
#undef SINEW_DECLARE_INPUTS
  std::vector<pipeline::ExternalInputRecord> records;
  for (const ExternalInputTable& e : external) {
    pipeline::ExternalInputRecord r{};
    if (e.name.empty() || e.name.size() >= sizeof(r.name))
      return layer_fail(e.where, "name must be 1..31 characters", error);
    if (e.unit.size() >= sizeof(r.unit)) return layer_fail(e.where, "unit must be at most 15 characters", error);
    pipeline::InputQuantity q;
    if (!quantity_of(e.quantity, &q))
      return layer_fail(e.where, "quantity must be \"force\", \"length\", \"angle\", \"scalar\" or \"acceleration\"",
                        error);
    if (!(e.min < e.max) || std::fabs(e.min) > 32767 || std::fabs(e.max) > 32767)
      return layer_fail(e.where, "min must be below max, both within +-32767", error);
    std::memcpy(r.name, e.name.data(), e.name.size());
    std::memcpy(r.unit, e.unit.data(), e.unit.size());
    r.quantity = static_cast<uint32_t>(q);
    r.min = q16(e.min);
    r.max = q16(e.max);
    records.push_back(r);
  }
  if (records.size() > pipeline::kMaxExternalInputs) return layer_fail("[[external_input]]", "at most 64", error);
  if (!records.empty()) sections.push_back(external_inputs_section(records));

  // Each layer in stage order.
  const LayerCompile c{spec, rig, g, layers.rate_hz, records, &sections, report};
#define SINEW_COMPILE_LAYER(name, enumerator, sections, doc) \
  if (!HostLayer<pipeline::Stage::enumerator>::compile(c, layers.name, error)) return false;
  SINEW_STAGE_LIST(SINEW_COMPILE_LAYER)
#undef SINEW_COMPILE_LAYER
  return append_layer_sections(blob, sections, error);
}

}  // namespace sinew::layers
