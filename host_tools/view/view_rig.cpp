#include "view_rig.hpp"

#include <sys/stat.h>

#include <cmath>
#include <cstring>

#include "hal/units/float_to_fixed.hpp"
#include "json_text.hpp"

namespace sinew::view {

namespace {

const char* unit_name(InputUnit u) {
  switch (u) {
    case InputUnit::kDegrees:
      return "deg";
    case InputUnit::kMetres:
      return "m";
    case InputUnit::kNewtons:
      return "N";
    case InputUnit::kRaw:
      return "";
  }
  return "";
}

}  // namespace

bool load_view_rig(const std::string& name_or_path, ViewRig* out, std::string* error) {
  struct stat st {};
  const bool is_file = ::stat(name_or_path.c_str(), &st) == 0;
  std::string builtin;
  if (!is_file) builtin = name_or_path.rfind("builtin:", 0) == 0 ? name_or_path.substr(8) : name_or_path;
  if (!is_file && builtin != "arm" && builtin != "hand")
    return *error = "--rig " + name_or_path + ": no such file, and not a built-in rig (arm, hand)", false;
  out->name = name_or_path;
  if (!firmware::load_rig(builtin, is_file ? name_or_path : "", &out->loaded, error)) return false;
  const rig::Rig& r = out->loaded.rig;
  out->input_unit.assign(out->loaded.input_count(), InputUnit::kDegrees);
  for (const rig::JointRecord& j : r.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d)
      if (j.dof_kind == static_cast<uint8_t>(rig::DofKind::kTranslation) && j.first_input + d < r.input_count)
        out->input_unit[j.first_input + d] = InputUnit::kMetres;
  for (size_t k = 0; k < out->loaded.external.size(); ++k)
    out->input_unit[r.input_count + k] = out->loaded.external[k].force ? InputUnit::kNewtons : InputUnit::kRaw;
  return true;
}

double input_display_value(const ViewRig& rig, uint32_t input, int32_t value) {
  switch (rig.input_unit[input]) {
    case InputUnit::kDegrees:
      return units::angle_to_degrees(static_cast<uint32_t>(value));
    case InputUnit::kMetres:
      return units::len_to_double(value, rig.loaded.rig.length_exponent);
    case InputUnit::kNewtons:
    case InputUnit::kRaw:
      return units::fixed_to_double(value, 16);  // Q15.16
  }
  return 0;
}

std::string rig_message_json(const ViewRig& rig, uint32_t tick_hz) {
  const rig::Rig& r = rig.loaded.rig;
  JsonText j;
  j.open_object();
  j.key("type").string("rig");
  j.key("name").string(rig.name);
  j.key("vertex_count").number(r.vertex_count());
  j.key("length_exponent").number(r.length_exponent);
  j.key("tick_hz").number(tick_hz);
  j.key("layers").string(firmware::describe_layers(rig.loaded));
  j.key("triangles").open_array();
  for (uint32_t t : r.triangles) j.number(t);
  j.close_array();
  j.key("joint_parent").open_array();
  for (const rig::JointRecord& jr : r.joints) j.number(jr.parent);
  j.close_array();
  j.key("joint_names").open_array();
  for (uint32_t k = 0; k < r.joint_count(); ++k)
    j.string(r.names.empty() ? "joint" + std::to_string(k)
                             : std::string(r.names[k], ::strnlen(r.names[k], sizeof r.names[k])));
  j.close_array();
  j.key("inputs").open_array();
  for (uint32_t i = 0; i < rig.loaded.input_count(); ++i) {
    j.open_object();
    j.key("name").string(rig.loaded.input_names[i]);
    j.key("unit").string(unit_name(rig.input_unit[i]));
    j.close_object();
  }
  j.close_array();
  j.close_object();
  return j.take();
}

}  // namespace sinew::view
