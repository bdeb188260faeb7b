#include "layer_compile.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::layers {

uint32_t LayerCompile::input_index(const std::string& name) const {
  uint32_t found = pipeline::kNoExternalInput;
  for (size_t k = 0; k < inputs.size(); ++k)
    if (!name.empty() && name == inputs[k].name) found = static_cast<uint32_t>(k);
  return found;
}

void declare_input(std::vector<ExternalInputTable>* external, const ExternalInputTable& input) {
  if (input.name.empty()) return;
  if (std::none_of(external->begin(), external->end(),
                   [&](const ExternalInputTable& e) { return e.name == input.name; }))
    external->push_back(input);
}

bool layer_fail(const std::string& where, const std::string& problem, std::string* error) {
  *error = where.empty() ? problem : where + ": " + problem;
  return false;
}

std::string report_number(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

int resolve_joint(const rigc::RigSpec& spec, const JointRef& ref, std::string* error) {
  if (ref.node >= 0) {
    for (size_t j = 0; j < spec.source_node.size(); ++j)
      if (spec.source_node[j] == ref.node) return static_cast<int>(j);
    layer_fail(ref.where,
               spec.source_node.empty() ? "joint by node index needs a glTF source"
                                        : "no joint of the rig comes from glTF node " + std::to_string(ref.node),
               error);
    return -1;
  }
  int j = rigc::joint_index(spec, ref.name);
  // A glTF name longer than the rig's 31 name bytes was truncated at import.
  if (j < 0 && ref.name.size() >= rig::kNameBytes) {
    size_t n = rig::kNameBytes - 1;
    while (n > 0 && (static_cast<unsigned char>(ref.name[n]) & 0xC0u) == 0x80u) --n;
    j = rigc::joint_index(spec, ref.name.substr(0, n));
  }
  if (j < 0) layer_fail(ref.where, "no joint named '" + ref.name + "'", error);
  return j;
}

}  // namespace sinew::layers
