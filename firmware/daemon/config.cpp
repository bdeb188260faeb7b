#include "config.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace sinew::firmware {
namespace {

std::string at(const std::string& origin, const toml::node* n, const std::string& key) {
  std::string s = origin;
  if (n != nullptr && n->source().begin.line > 0) s += ":" + std::to_string(n->source().begin.line);
  return s + ": " + key;
}

template <typename T>
bool read_number(const toml::table& t, const char* key, T lo, T hi, T* out, const std::string& origin,
                 std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value<double>();
  if (!v || !(*v >= static_cast<double>(lo) && *v <= static_cast<double>(hi))) {
    std::ostringstream s;
    s << at(origin, n, key) << ": must be a number in [" << lo << ", " << hi << "]";
    *error = s.str();
    return false;
  }
  *out = static_cast<T>(*v);
  return true;
}

bool read_flag(const toml::table& t, const char* key, bool* out, const std::string& origin, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<bool>();
  if (!v) return *error = at(origin, n, key) + ": must be true or false", false;
  *out = *v;
  return true;
}

// A misspelt key would otherwise be ignored and its default used in silence.
bool known_keys_only(const toml::table& t, const char* table, std::initializer_list<std::string_view> keys,
                     const std::string& origin, std::string* error) {
  for (const auto& [key, node] : t) {
    if (std::find(keys.begin(), keys.end(), key.str()) != keys.end()) continue;
    std::string known;
    for (std::string_view k : keys) known += (known.empty() ? "" : ", ") + std::string(k);
    return *error = at(origin, &node, std::string("[") + table + "] " + std::string(key.str())) + ": unknown key (" +
                    known + ")",
           false;
  }
  return true;
}

}  // namespace

bool parse_config(std::string_view text, const std::string& origin, DaemonConfig* out, std::string* error) {
  toml::table t;
  try {
    t = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    *error = origin + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description());
    return false;
  }
  DaemonConfig c;
  for (const char* table : {"rig", "loop", "layers", "realtime", "inputs"})
    if (t.contains(table) && !t[table].is_table())
      return *error = at(origin, t[table].node(), std::string("[") + table + "]") + ": must be a table", false;
  for (const auto& [key, node] : t)
    if (std::string_view k = key.str();
        k != "rig" && k != "loop" && k != "layers" && k != "realtime" && k != "inputs" && k != "source" && k != "sink")
      return *error = at(origin, &node, std::string(k)) +
                      ": unknown table or key (rig, loop, layers, realtime, inputs, source, sink)",
             false;
  if (const toml::table* rig = t["rig"].as_table()) {
    if (!known_keys_only(*rig, "rig", {"builtin", "blob"}, origin, error)) return false;
    c.rig_builtin = (*rig)["builtin"].value_or<std::string>("");
    c.rig_blob = (*rig)["blob"].value_or<std::string>("");
  }
  if (c.rig_builtin.empty() == c.rig_blob.empty())
    return *error = origin + ": [rig] needs exactly one of builtin = \"arm\"|\"hand\" or blob = \"file.rig\"", false;
  if (!c.rig_builtin.empty() && c.rig_builtin != "arm" && c.rig_builtin != "hand")
    return *error = at(origin, t["rig"]["builtin"].node(), "[rig] builtin") + ": unknown built-in rig (arm, hand)",
           false;
  if (const toml::table* loop = t["loop"].as_table()) {
    if (!known_keys_only(*loop, "loop", {"rate_hz", "duration_s", "stats_interval_s", "mode"}, origin, error))
      return false;
    if (!read_number(*loop, "rate_hz", 1u, 20000u, &c.rate_hz, origin, error)) return false;
    if (!read_number(*loop, "duration_s", 0.0, 1e7, &c.duration_s, origin, error)) return false;
    if (!read_number(*loop, "stats_interval_s", 0.0, 3600.0, &c.stats_interval_s, origin, error)) return false;
    const std::string mode = (*loop)["mode"].value_or<std::string>("live");
    if (mode == "live")
      c.mode = RunMode::kLive;
    else if (mode == "replay")
      c.mode = RunMode::kReplay;
    else if (mode == "offline")
      c.mode = RunMode::kOffline;
    else
      return *error = at(origin, (*loop)["mode"].node(), "[loop] mode") + ": must be live, replay or offline", false;
  }
  if (const toml::table* layers = t["layers"].as_table()) {
    // The layers are compiled into the rig (rigc, docs/rig-format.md); here
    // they are only switched on or off and given run-time options.
    for (const char* old : {"anatomy_iterations", "sph_particles", "sph_force_max_n"})
      if (layers->contains(old))
        return *error = at(origin, (*layers)[old].node(), std::string("[layers] ") + old) +
                        ": layers are compiled into the rig now: set their parameters in the rig spec "
                        "([[sph]] particles, [skin] iterations, [[external_input]] min/max) and switch them "
                        "on here with sph, metaballs, barnet, anatomy = true",
               false;
    if (!known_keys_only(*layers, "layers", {"sph", "metaballs", "barnet", "anatomy", "skin_iterations", "tresca"},
                         origin, error) ||
        !read_flag(*layers, "sph", &c.layer_sph, origin, error) ||
        !read_flag(*layers, "metaballs", &c.layer_metaballs, origin, error) ||
        !read_flag(*layers, "barnet", &c.layer_barnet, origin, error) ||
        !read_flag(*layers, "anatomy", &c.layer_anatomy, origin, error) ||
        !read_flag(*layers, "tresca", &c.layer_tresca, origin, error) ||
        !read_number(*layers, "skin_iterations", 0, 256, &c.layer_skin_iterations, origin, error))
      return false;
  }
  if (const toml::table* rt = t["realtime"].as_table()) {
    if (!known_keys_only(*rt, "realtime", {"fifo_priority", "cpu", "lock_memory"}, origin, error)) return false;
    if (!read_number(*rt, "fifo_priority", 0, 99, &c.realtime.fifo_priority, origin, error)) return false;
    if (!read_number(*rt, "cpu", -1, 1023, &c.realtime.cpu, origin, error)) return false;
    if (!read_flag(*rt, "lock_memory", &c.realtime.lock_memory, origin, error)) return false;
  }
  if (const toml::table* in = t["inputs"].as_table()) {
    if (!known_keys_only(*in, "inputs", {"timeout_factor", "default_period_ms", "range_margin_deg"}, origin, error))
      return false;
    if (!read_number(*in, "timeout_factor", 1.0, 100.0, &c.timeout_factor, origin, error)) return false;
    if (!read_number(*in, "default_period_ms", 0.01, 10000.0, &c.default_period_ms, origin, error)) return false;
    if (!read_number(*in, "range_margin_deg", 0.0, 180.0, &c.range_margin_deg, origin, error)) return false;
  }
  const auto read_list = [&](const char* key, auto* list) {
    const toml::array* a = t[key].as_array();
    if (a == nullptr) return true;
    for (const toml::node& n : *a) {
      const toml::table* e = n.as_table();
      const auto type = e != nullptr ? (*e)["type"].value<std::string>() : std::nullopt;
      if (!type) return *error = at(origin, &n, std::string("[[") + key + "]] type") + " is required", false;
      const std::string name = (*e)["name"].value_or<std::string>(std::string(*type));
      list->push_back({*type, name, *e});
    }
    return true;
  };
  if (!read_list("source", &c.sources) || !read_list("sink", &c.sinks)) return false;
  *out = std::move(c);
  return true;
}

bool load_config(const std::string& path, DaemonConfig* out, std::string* error) {
  std::ifstream f(path);
  if (!f) return *error = path + ": cannot open", false;
  std::stringstream s;
  s << f.rdbuf();
  return parse_config(s.str(), path, out, error);
}

}  // namespace sinew::firmware
