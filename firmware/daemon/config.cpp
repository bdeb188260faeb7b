#include "config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <span>
#include <sstream>

#include "config_keys.hpp"
#include "config_registry.hpp"
#include "sim_core/layer/workers.hpp"
#include "sim_core/pipeline/stage_table.hpp"
#include "sinks.hpp"
#include "sources.hpp"

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
bool known_keys_only(const toml::table& t, const char* table, std::span<const std::string_view> keys,
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

// [layers]: the layers are compiled into the rig (rigc, docs/rig-format.md);
// here a compiled layer is only switched on or off and given its run-time
// options. The keys and their ranges are the stage table's.
bool read_layers(const toml::table& t, const std::string& origin, pipeline::PipelineOptions* o, std::string* error) {
  std::vector<std::string_view> keys;
  for (const pipeline::StageInfo& s : pipeline::kStages)
    if (s.stage != pipeline::Stage::kSkinning) keys.emplace_back(s.name);
  for (const pipeline::StageOption& option : pipeline::kStageOptions) keys.emplace_back(option.key);
  for (const auto& [key, node] : t) {
    if (std::find(keys.begin(), keys.end(), key.str()) != keys.end()) continue;
    std::string known;
    for (std::string_view k : keys) known += (known.empty() ? "" : ", ") + std::string(k);
    return *error = at(origin, &node, "[layers] " + std::string(key.str())) + ": unknown key (" + known +
                    "); a layer's parameters are compiled into the rig: set them in the rig's spec (rigc) and "
                    "switch the layer on here",
           false;
  }
  for (const pipeline::StageInfo& s : pipeline::kStages) {
    if (s.stage == pipeline::Stage::kSkinning) continue;
    bool on = o->stages.has(s.stage);
    if (!read_flag(t, s.name, &on, origin, error)) return false;
    o->stages.set(s.stage, on);
  }
  for (const pipeline::StageOption& option : pipeline::kStageOptions) {
    switch (option.kind) {
      case pipeline::OptionKind::kFlag:
        if (!read_flag(t, option.key, option.flag(o), origin, error)) return false;
        break;
      case pipeline::OptionKind::kNumber:
        if (!read_number<uint32_t>(t, option.key, option.min, option.max, option.number(o), origin, error))
          return false;
        break;
      case pipeline::OptionKind::kChoice:
        if (const toml::node* n = t.get(option.key)) {
          const std::optional<std::string> v = n->value_exact<std::string>();
          if (!v || (*v != option.choice[0] && *v != option.choice[1]))
            return *error = at(origin, n, std::string("[layers] ") + option.key) + ": must be \"" + option.choice[0] +
                            "\" or \"" + option.choice[1] + "\"",
                   false;
          *option.flag(o) = *v == option.choice[1];
        }
        break;
    }
  }
  return true;
}

using Kind = KeyKind;
using Key = ConfigKey;

std::string range_text(double lo, double hi) {
  std::ostringstream s;
  s.precision(12);
  s << "[" << lo << ", " << hi << "]";
  return s.str();
}

// "[[source]]" -> "source"
std::string bare(const std::string& table) {
  std::string s;
  for (char ch : table)
    if (ch != '[' && ch != ']') s += ch;
  return s;
}

bool check_keys(const toml::table& t, const std::string& table, std::span<const Key> keys, const std::string& origin,
                std::string* error) {
  for (const auto& entry : t) {
    // Named references, not a structured binding: lambdas below capture them.
    const toml::key& name = entry.first;
    const toml::node& node = entry.second;
    const auto key = std::find_if(keys.begin(), keys.end(), [&](const Key& k) { return k.name == name.str(); });
    const std::string what = table + " " + std::string(name.str());
    if (key == keys.end()) {
      std::string known;
      for (const Key& k : keys) known += (known.empty() ? "" : ", ") + std::string(k.name);
      return *error = at(origin, &node, what) + ": unknown key (" + known + ")", false;
    }
    const auto fail = [&](const std::string& must) { return *error = at(origin, &node, what) + ": " + must, false; };
    switch (key->kind) {
      case Kind::kString:
        if (!node.is_string()) return fail("must be a string");
        break;
      case Kind::kFlag:
        if (!node.is_boolean()) return fail("must be true or false");
        break;
      case Kind::kChoice: {
        const std::optional<std::string> v = node.value_exact<std::string>();
        if (!v || std::find(key->choices.begin(), key->choices.end(), *v) == key->choices.end()) {
          std::string names;
          for (size_t i = 0; i < key->choices.size(); ++i)
            names += (i == 0 ? "" : (i + 1 == key->choices.size() ? " or " : ", ")) +
                     ("\"" + std::string(key->choices[i]) + "\"");
          return fail("must be " + names);
        }
        break;
      }
      case Kind::kInput:
        if (!node.is_string() && !node.is_integer()) return fail("must be an input name or index");
        break;
      case Kind::kInteger: {
        const auto v = node.value_exact<int64_t>();
        if (!v || static_cast<double>(*v) < key->lo || static_cast<double>(*v) > key->hi)
          return fail("must be an integer in " + range_text(key->lo, key->hi));
        break;
      }
      case Kind::kNumber: {
        const auto v = node.is_number() ? node.value<double>() : std::nullopt;
        if (!v || !std::isfinite(*v) || *v < key->lo || *v > key->hi)
          return fail("must be a number in " + range_text(key->lo, key->hi));
        break;
      }
      case Kind::kTable:
        if (!node.is_table()) return fail("must be a table");
        if (!check_keys(*node.as_table(), "[" + bare(table) + "." + std::string(name.str()) + "]", key->sub, origin,
                        error))
          return false;
        break;
      case Kind::kTables: {
        const toml::array* a = node.as_array();
        if (a == nullptr || !a->is_array_of_tables()) return fail("must be [[tables]]");
        const std::string sub = "[[" + bare(table) + "." + std::string(name.str()) + "]]";
        for (const toml::node& e : *a)
          if (!check_keys(*e.as_table(), sub, key->sub, origin, error)) return false;
        break;
      }
    }
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
  for (const char* table : {"rig", "loop", "layers", "realtime", "inputs", "status"})
    if (t.contains(table) && !t[table].is_table())
      return *error = at(origin, t[table].node(), std::string("[") + table + "]") + ": must be a table", false;
  for (const auto& [key, node] : t)
    if (std::string_view k = key.str(); k != "rig" && k != "loop" && k != "layers" && k != "realtime" &&
                                        k != "inputs" && k != "status" && k != "source" && k != "sink")
      return *error = at(origin, &node, std::string(k)) +
                      ": unknown table or key (rig, loop, layers, realtime, inputs, status, source, sink)",
             false;
  if (const toml::table* rig = t["rig"].as_table()) {
    constexpr std::string_view kRigKeys[] = {"builtin", "blob"};
    if (!known_keys_only(*rig, "rig", kRigKeys, origin, error)) return false;
    c.rig_builtin = (*rig)["builtin"].value_or<std::string>("");
    c.rig_blob = (*rig)["blob"].value_or<std::string>("");
  }
  if (c.rig_builtin.empty() == c.rig_blob.empty())
    return *error = origin + ": [rig] needs exactly one of builtin = \"arm\"|\"hand\" or blob = \"file.rig\"", false;
  if (!c.rig_builtin.empty() && c.rig_builtin != "arm" && c.rig_builtin != "hand")
    return *error = at(origin, t["rig"]["builtin"].node(), "[rig] builtin") + ": unknown built-in rig (arm, hand)",
           false;
  if (const toml::table* loop = t["loop"].as_table()) {
    if (!known_keys_only(*loop, "loop", daemon_keys_of("loop"), origin, error)) return false;
    if (!read_number(*loop, "rate_hz", 1u, 20000u, &c.rate_hz, origin, error)) return false;
    if (!read_number(*loop, "duration_s", 0.0, 1e7, &c.duration_s, origin, error)) return false;
    if (!read_number(*loop, "stats_interval_s", 0.0, 3600.0, &c.stats_interval_s, origin, error)) return false;
    const toml::node* mode_node = loop->get("mode");
    if (mode_node != nullptr && !mode_node->is_string())
      return *error = at(origin, mode_node, "[loop] mode") + ": must be live, replay or offline", false;
    const std::string mode = (*loop)["mode"].value_or<std::string>("live");
    if (mode == "live")
      c.mode = RunMode::kLive;
    else if (mode == "replay")
      c.mode = RunMode::kReplay;
    else if (mode == "offline")
      c.mode = RunMode::kOffline;
    else
      return *error = at(origin, (*loop)["mode"].node(), "[loop] mode") + ": must be live, replay or offline", false;
    if (const toml::node* trigger = loop->get("trigger")) {
      const std::optional<std::string> name = trigger->value_exact<std::string>();
      const TickTrigger all[] = {TickTrigger::kPeriodic, TickTrigger::kInputs, TickTrigger::kSync};
      const auto it = std::find_if(std::begin(all), std::end(all),
                                   [&](TickTrigger k) { return name && *name == tick_trigger_name(k); });
      if (it == std::end(all))
        return *error = at(origin, trigger, "[loop] trigger") + ": must be \"periodic\", \"inputs\" or \"sync\"", false;
      c.trigger = *it;
    }
    if (!read_number(*loop, "trigger_poll_us", 1.0, 1000.0, &c.trigger_poll_us, origin, error)) return false;
    if (!read_number(*loop, "step_budget", 0.0, 1.0, &c.step_budget, origin, error)) return false;
    if (const toml::node* over = loop->get("over_budget")) {
      const std::optional<std::string> name = over->value_exact<std::string>();
      if (name == "warn")
        c.over_budget = OverBudget::kWarn;
      else if (name == "slow")
        c.over_budget = OverBudget::kSlow;
      else if (name == "refuse")
        c.over_budget = OverBudget::kRefuse;
      else
        return *error = at(origin, over, "[loop] over_budget") + ": must be \"warn\", \"slow\" or \"refuse\"", false;
    }
  }
  if (const toml::table* layers = t["layers"].as_table())
    if (!read_layers(*layers, origin, &c.layers, error)) return false;
  if (const toml::table* st = t["status"].as_table()) {
    if (!known_keys_only(*st, "status", daemon_keys_of("status"), origin, error)) return false;
    if (!read_number(*st, "modbus_port", -1, 65535, &c.status.modbus_port, origin, error)) return false;
    if (!read_number(*st, "modbus_max_clients", 1, 64, &c.status.modbus_max_clients, origin, error)) return false;
    if (const toml::node* bind = st->get("modbus_bind")) {
      if (!bind->is_string()) return *error = at(origin, bind, "[status] modbus_bind") + ": must be a string", false;
      c.status.modbus_bind = bind->value_or<std::string>("");
    }
  }
  if (const toml::table* rt = t["realtime"].as_table()) {
    if (!known_keys_only(*rt, "realtime", daemon_keys_of("realtime"), origin, error)) return false;
    if (!read_number(*rt, "fifo_priority", 0, 99, &c.realtime.fifo_priority, origin, error)) return false;
    if (!read_number(*rt, "cpu", -1, 1023, &c.realtime.cpu, origin, error)) return false;
    if (!read_flag(*rt, "lock_memory", &c.realtime.lock_memory, origin, error)) return false;
    if (!read_number(*rt, "cpu_latency_us", -1, 1'000'000, &c.realtime.cpu_latency_us, origin, error)) return false;
    if (!read_number(*rt, "io_fifo_priority", 0, 99, &c.realtime.io_fifo_priority, origin, error)) return false;
    if (!read_number(*rt, "io_cpu", -1, 1023, &c.realtime.io_cpu, origin, error)) return false;
    if (!read_number(*rt, "sink_ring_frames", 1, 65536, &c.realtime.sink_ring_frames, origin, error)) return false;
    if (!read_number(*rt, "io_poll_us", 0, 100000, &c.realtime.io_poll_us, origin, error)) return false;
    if (!read_number(*rt, "workers", 0, static_cast<int>(layer::kMaxParts), &c.realtime.workers, origin, error))
      return false;
    if (!read_number(*rt, "worker_cpu", -1, 1023, &c.realtime.worker_cpu, origin, error)) return false;
    if (const toml::node* user = rt->get("user")) {
      const std::optional<std::string> name = user->value_exact<std::string>();
      if (!name) return *error = at(origin, user, "[realtime] user") + ": must be a user name (a string)", false;
      c.realtime.user = *name;
    }
    // A polled I/O thread must come round at least twice while its ring
    // fills, or a full ring drops frames however fast the sink is.
    const uint64_t ring_us = static_cast<uint64_t>(c.realtime.sink_ring_frames) * 1'000'000u / c.rate_hz;
    if (c.realtime.io_poll_us > 0 && 2u * static_cast<uint64_t>(c.realtime.io_poll_us) > ring_us) {
      *error = origin + ": [realtime] io_poll_us = " + std::to_string(c.realtime.io_poll_us) +
               " is more than half the ring's " + std::to_string(ring_us) + " us (sink_ring_frames " +
               std::to_string(c.realtime.sink_ring_frames) + " at " + std::to_string(c.rate_hz) + " Hz)";
      return false;
    }
  }
  if (const toml::table* in = t["inputs"].as_table()) {
    if (!known_keys_only(*in, "inputs", daemon_keys_of("inputs"), origin, error)) return false;
    if (!read_number(*in, "timeout_factor", 1.0, 100.0, &c.timeout_factor, origin, error)) return false;
    if (!read_number(*in, "default_period_ms", 0.01, 10000.0, &c.default_period_ms, origin, error)) return false;
    if (!read_number(*in, "range_margin_deg", 0.0, 180.0, &c.range_margin_deg, origin, error)) return false;
  }
  const auto read_list = [&](const char* key, auto types, auto* list) {
    const toml::node* node = t.get(key);
    if (node == nullptr) return true;
    const toml::array* a = node->as_array();
    if (a == nullptr || !a->is_array_of_tables())
      return *error = at(origin, node, std::string("[[") + key + "]]") + ": must be [[tables]]", false;
    const std::string table = std::string("[[") + key + "]]";
    for (const toml::node& n : *a) {
      const toml::table* e = n.as_table();
      const auto type = (*e)["type"].value_exact<std::string>();
      if (!type) return *error = at(origin, &n, table + " type") + " is required (a string)", false;
      const auto it = std::find_if(types.begin(), types.end(), [&](const auto& k) { return k.type == *type; });
      if (it == types.end()) {
        std::string known;
        for (const auto& k : types) known += (known.empty() ? "" : ", ") + std::string(k.type);
        return *error =
                   at(origin, (*e)["type"].node(), table + " type") + ": unknown type '" + *type + "' (" + known + ")",
               false;
      }
      if (!check_keys(*e, table, it->keys, origin, error)) return false;
      const std::string name = (*e)["name"].value_or<std::string>(std::string(*type));
      // Sources and sinks are reported, and their errors given, by name.
      for (const auto& other : *list)
        if (other.name == name)
          return *error = at(origin, &n, table + " name") + ": '" + name + "' is used twice (give each a name)", false;
      list->push_back({*type, name, *e});
    }
    return true;
  };
  if (!read_list("source", source_types(), &c.sources) || !read_list("sink", sink_types(), &c.sinks)) return false;
  *out = std::move(c);
  return true;
}

bool load_config(const std::string& path, DaemonConfig* out, std::string* error) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return *error = path + ": is a directory, not a config file", false;
  std::ifstream f(path);
  if (!f) return *error = path + ": cannot open", false;
  std::stringstream s;
  s << f.rdbuf();
  return parse_config(s.str(), path, out, error);
}

}  // namespace sinew::firmware
