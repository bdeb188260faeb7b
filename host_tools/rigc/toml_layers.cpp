#include "toml_layers.hpp"

#include "host_tools/rigc/toml_reader.hpp"
// One line per layer: its tables' reader.
#include "host_tools/rigc/tables/anatomy_table.hpp"
#include "host_tools/rigc/tables/barnet_table.hpp"
#include "host_tools/rigc/tables/metaballs_table.hpp"
#include "host_tools/rigc/tables/sph_table.hpp"

namespace sinew::rigc {

using namespace spec_read;

bool is_layer_table(std::string_view key) {
  bool owned = false;
#define SINEW_LAYER_OWNS(name, enumerator, sections, doc) \
  owned = owned || RigcTable<pipeline::Stage::enumerator>::owns(key);
  SINEW_STAGE_LIST(SINEW_LAYER_OWNS)
#undef SINEW_LAYER_OWNS
  return owned || key == "external_input";
}

bool read_toml_layers(const std::string& path, const toml::table& t, layers::LayerSpecs* out, std::string* error) {
  layers::LayerSpecs s;
  if (const toml::table* rig = t["rig"].as_table())
    if (!read_int(path, *rig, "[rig]", "rate_hz", 13, 100000, &s.rate_hz, error)) return false;
      // Each layer's tables, in stage order.
#define SINEW_READ_LAYER_TABLES(name, enumerator, sections, doc) \
  if (!RigcTable<pipeline::Stage::enumerator>::read(path, t, &s.name, error)) return false;
  SINEW_STAGE_LIST(SINEW_READ_LAYER_TABLES)
#undef SINEW_READ_LAYER_TABLES
  // The inputs the layers read, declared by the spec.
  const bool ok = each_table(
      path, t, "external_input",
      [&](const toml::table& e) {
        layers::ExternalInputTable x;
        const std::string n = "[[external_input]]";
        x.where = at(path, &e, n);
        if (!known_keys(path, e, n, {"name", "unit", "quantity", "min", "max"}, error) ||
            !read_string(path, e, n, "name", &x.name, error) || !read_string(path, e, n, "unit", &x.unit, error) ||
            !read_string(path, e, n, "quantity", &x.quantity, error) ||
            !read_number(path, e, n, "min", &x.min, error) || !read_number(path, e, n, "max", &x.max, error))
          return false;
        if (x.name.empty() || !e.contains("min") || !e.contains("max"))
          return *error = x.where + ": name, unit, min and max are required", false;
        s.external.push_back(x);
        return true;
      },
      error);
  if (!ok) return false;
  *out = std::move(s);
  return true;
}

}  // namespace sinew::rigc
