#include "builtin_layers.hpp"

#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::layers {
namespace {

// The layer tables of a built-in rig: every layer, at the joints it names.
struct BuiltinJoints {
  const char* sph;            // the SPH tissue's joint
  uint32_t sph_particles;     // and its particle count
  const char* muscle;         // the muscle's name
  const char* muscle_origin;  // its origin and insertion joints
  const char* muscle_insertion;
  const char* barnet;  // the bar-net's joint
};

LayerSpecs builtin_tables(const std::string& spec, const BuiltinJoints& j) {
  LayerSpecs s;
  s.sph.push_back({{j.sph, -1, spec + ": [[sph]] joint"}, j.sph_particles, 0, 0, 0, 0, ""});
  s.metaballs = {true, spec + ": [metaballs]", 0, {}};
  s.anatomy.muscles.push_back({j.muscle,
                               {j.muscle_origin, -1, spec + ": [[muscle]] origin"},
                               {j.muscle_insertion, -1, spec + ": [[muscle]] insertion"},
                               {0, 0, 0},
                               1.0,
                               spec + ": [[muscle]]"});
  s.anatomy.skin.on = true;
  s.anatomy.skin.where = spec + ": [skin]";
  s.anatomy.skin.iterations = 4;
  s.anatomy.skin.warm_start = true;
  s.barnet.push_back({{j.barnet, -1, spec + ": [[barnet]] joint"}, 8, 7, 0, 0});
  return s;
}

}  // namespace

bool builtin_layers(const std::string& name, LayerSpecs* out) {
  const std::string spec = "rigs/" + name + ".toml";
  if (name == "arm")
    *out = builtin_tables(spec, {"elbow", 500, "biceps", "shoulder", "elbow", "elbow"});
  else if (name == "hand")
    *out = builtin_tables(spec, {"index_pip", 300, "index_flexor", "index_mcp", "index_pip", "middle_pip"});
  else
    return false;
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
