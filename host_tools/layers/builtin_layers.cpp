#include "builtin_layers.hpp"

#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::layers {

bool builtin_layers(const std::string& name, LayerSpecs* out) {
  LayerSpecs s;
  const std::string spec = "rigs/" + name + ".toml";
  if (name == "arm") {
    s.sph.push_back({{"elbow", -1, spec + ": [[sph]] joint"}, 500, 0, 0, 0, 60, ""});
    s.metaballs = {true, spec + ": [metaballs]", 0, {}};
    s.muscles.push_back({"biceps",
                         {"shoulder", -1, spec + ": [[muscle]] origin"},
                         {"elbow", -1, spec + ": [[muscle]] insertion"},
                         {0, 0, 0},
                         1.0,
                         spec + ": [[muscle]]"});
    s.skin.on = true;
    s.skin.where = spec + ": [skin]";
    s.skin.iterations = 4;
    s.skin.warm_start = true;
    s.barnets.push_back({{"elbow", -1, spec + ": [[barnet]] joint"}, 8, 7, 0, 0});
  } else if (name == "hand") {
    s.sph.push_back({{"index_pip", -1, spec + ": [[sph]] joint"}, 300, 0, 0, 0, 60, ""});
    s.metaballs = {true, spec + ": [metaballs]", 0, {}};
    s.muscles.push_back({"index_flexor",
                         {"index_mcp", -1, spec + ": [[muscle]] origin"},
                         {"index_pip", -1, spec + ": [[muscle]] insertion"},
                         {0, 0, 0},
                         1.0,
                         spec + ": [[muscle]]"});
    s.skin.on = true;
    s.skin.where = spec + ": [skin]";
    s.skin.iterations = 4;
    s.skin.warm_start = true;
    s.barnets.push_back({{"middle_pip", -1, spec + ": [[barnet]] joint"}, 8, 7, 0, 0});
  } else {
    return false;
  }
  *out = std::move(s);
  return true;
}

bool compile_builtin(const std::string& name, std::vector<uint8_t>* blob, std::vector<std::string>* report,
                     std::string* error) {
  rigc::RigSpec spec;
  LayerSpecs layers;
  if (!rigc::builtin_rig(name, rigc::SkinChoice::kDualQuaternion, &spec) || !builtin_layers(name, &layers))
    return *error = "unknown built-in rig '" + name + "' (arm, hand)", false;
  rigc::CompileReport core;
  return add_layer_dofs(&spec, layers, report, error) && rigc::compile_rig(spec, blob, &core, error) &&
         compile_layers(spec, layers, blob, report, error);
}

}  // namespace sinew::layers
