#include "config_registry.hpp"

#include <cstdio>
#include <sstream>

#include "sim_core/pipeline/stage_table.hpp"
#include "sinks.hpp"
#include "sources.hpp"

namespace sinew::firmware {

namespace {

std::string number(double v) {
  char s[64];
  std::snprintf(s, sizeof(s), "%.17g", v);
  std::string out = s;
  if (out.find_first_of(".eEn") == std::string::npos) out += ".0";  // a TOML float stays a float
  return out;
}
std::string integer(int64_t v) { return std::to_string(v); }
std::string flag(bool v) { return v ? "true" : "false"; }
std::string quoted(const std::string& v) {
  std::string out = "\"";
  for (const char ch : v) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}
const char* mode_name(RunMode m) {
  return m == RunMode::kLive ? "live" : (m == RunMode::kReplay ? "replay" : "offline");
}
const char* over_budget_name(OverBudget o) {
  return o == OverBudget::kWarn ? "warn" : (o == OverBudget::kSlow ? "slow" : "refuse");
}

// clang-format off
constexpr DaemonKey kKeys[] = {
    {"loop", "rate_hz", "1000", "ticks per second, 1..20000",
     [](const DaemonConfig& c) { return integer(c.rate_hz); }},
    {"loop", "duration_s", "0.0", "seconds of schedule to run; 0: until SIGINT/SIGTERM",
     [](const DaemonConfig& c) { return number(c.duration_s); }},
    {"loop", "stats_interval_s", "1.0", "seconds between statistics lines; 0: only the final report",
     [](const DaemonConfig& c) { return number(c.stats_interval_s); }},
    {"loop", "mode", "\"live\"", "live | replay | offline",
     [](const DaemonConfig& c) { return quoted(mode_name(c.mode)); }},
    {"loop", "trigger", "\"periodic\"", "periodic | inputs | sync: when a live tick starts (docs/pipeline.md)",
     [](const DaemonConfig& c) { return quoted(tick_trigger_name(c.trigger)); }},
    {"loop", "trigger_poll_us", "20.0", "how often the sources are asked while a triggered tick waits, 1..1000",
     [](const DaemonConfig& c) { return number(c.trigger_poll_us); }},
    {"loop", "step_budget", "0.5", "share of the period the start-up tick's p99 may take; 0: not measured",
     [](const DaemonConfig& c) { return number(c.step_budget); }},
    {"loop", "over_budget", "\"warn\"", "warn | slow | refuse: a live run over the budget (docs/pipeline.md)",
     [](const DaemonConfig& c) { return quoted(over_budget_name(c.over_budget)); }},
    {"realtime", "fifo_priority", "0", "1..99: SCHED_FIFO for the tick thread (needs CAP_SYS_NICE); 0: default policy",
     [](const DaemonConfig& c) { return integer(c.realtime.fifo_priority); }},
    {"realtime", "cpu", "-1", "pin the tick thread to a CPU; -1: no affinity",
     [](const DaemonConfig& c) { return integer(c.realtime.cpu); }},
    {"realtime", "lock_memory", "false", "mlockall (needs CAP_IPC_LOCK or a large RLIMIT_MEMLOCK)",
     [](const DaemonConfig& c) { return flag(c.realtime.lock_memory); }},
    {"realtime", "cpu_latency_us", "0",
     "-1..1000000: the CPUs' wake-up latency requested for a live run (/dev/cpu_dma_latency); -1: none",
     [](const DaemonConfig& c) { return integer(c.realtime.cpu_latency_us); }},
    {"realtime", "workers", "0", "threads of the parallel stages, the tick's included; 0: the CPUs but one",
     [](const DaemonConfig& c) { return integer(c.realtime.workers); }},
    {"realtime", "worker_cpu", "-1", "pin worker i (1..workers-1) to CPU worker_cpu + i - 1; -1: no affinity",
     [](const DaemonConfig& c) { return integer(c.realtime.worker_cpu); }},
    {"realtime", "io_fifo_priority", "0", "1..99: SCHED_FIFO for the sinks' I/O threads; 0: default policy",
     [](const DaemonConfig& c) { return integer(c.realtime.io_fifo_priority); }},
    {"realtime", "io_cpu", "-1", "pin the I/O threads to a CPU; -1: no affinity",
     [](const DaemonConfig& c) { return integer(c.realtime.io_cpu); }},
    {"realtime", "sink_ring_frames", "128", "frames queued per sink, 1..65536",
     [](const DaemonConfig& c) { return integer(c.realtime.sink_ring_frames); }},
    {"realtime", "user", "\"\"", "after opening devices as root, run as this user (\"\": as started)",
     [](const DaemonConfig& c) { return quoted(c.realtime.user); }},
    {"realtime", "io_poll_us", "0", "0: a wake per frame; 1..100000: the I/O threads drain every io_poll_us",
     [](const DaemonConfig& c) { return integer(c.realtime.io_poll_us); }},
    {"inputs", "timeout_factor", "1.5", "an input is stale after this x its expected period",
     [](const DaemonConfig& c) { return number(c.timeout_factor); }},
    {"inputs", "default_period_ms", "10.0", "the expected sample period of a source that does not say",
     [](const DaemonConfig& c) { return number(c.default_period_ms); }},
    {"inputs", "range_margin_deg", "10.0", "accepted beyond a joint limit (then clamped); further: a sensor fault",
     [](const DaemonConfig& c) { return number(c.range_margin_deg); }},
    {"status", "modbus_port", "-1", "Modbus TCP status registers on this port; 0: any free port; -1: none",
     [](const DaemonConfig& c) { return integer(c.status.modbus_port); }},
    {"status", "modbus_bind", "\"127.0.0.1\"", "the status server's IPv4 address; \"0.0.0.0\": every interface",
     [](const DaemonConfig& c) { return quoted(c.status.modbus_bind); }},
    {"status", "modbus_max_clients", "4", "clients served at once, 1..64",
     [](const DaemonConfig& c) { return integer(c.status.modbus_max_clients); }},
};
// clang-format on

constexpr std::string_view kTables[] = {"loop", "realtime", "inputs", "status"};

void layers_text(const pipeline::PipelineOptions& o, std::ostringstream& out) {
  out << "\n[layers]\n";
  for (const pipeline::StageInfo& s : pipeline::kStages)
    if (s.stage != pipeline::Stage::kSkinning)
      out << s.name << " = " << flag(o.stages.has(s.stage)) << "  # " << s.rig_sections << " in the rig's spec\n";
  for (const pipeline::StageOption& option : pipeline::kStageOptions) {
    out << option.key << " = ";
    const uint32_t v = pipeline::option_value(option, o);
    switch (option.kind) {
      case pipeline::OptionKind::kFlag:
        out << flag(v != 0);
        break;
      case pipeline::OptionKind::kNumber:
        out << v;
        break;
      case pipeline::OptionKind::kChoice:
        out << quoted(option.choice[v != 0 ? 1 : 0]);
        break;
    }
    out << "\n";
  }
}

// A [[source]] or [[sink]] table printed under its header: nested tables
// and arrays of tables inline, so the printed text parses back as given.
void inline_nested(toml::node& n) {
  if (toml::table* t = n.as_table()) {
    t->is_inline(true);
    for (auto&& [k, v] : *t) inline_nested(v);
  } else if (toml::array* a = n.as_array()) {
    for (toml::node& e : *a) inline_nested(e);
  }
}

void entry_text(const char* header, const toml::table& given, std::ostringstream& out) {
  toml::table t = given;
  for (auto&& [k, v] : t) inline_nested(v);
  out << "\n" << header << "  # as given; the type's defaults apply to the keys it leaves out\n" << t << "\n";
}

void types_text(std::ostringstream& out) {
  out << "\n# [[source]] types:";
  for (const SourceType& t : source_types()) out << " " << t.type;
  out << "\n# [[sink]] types:";
  for (const SinkType& t : sink_types()) out << " " << t.type;
  out << "\n# (their keys: firmware/config/default.toml and docs/)\n";
}

}  // namespace

std::span<const DaemonKey> daemon_keys() { return kKeys; }

std::vector<std::string_view> daemon_keys_of(std::string_view table) {
  std::vector<std::string_view> keys;
  for (const DaemonKey& k : kKeys)
    if (k.table == table) keys.push_back(k.key);
  return keys;
}

std::string default_config_text() {
  std::ostringstream out;
  out << "# sinewd: every key of [loop], [realtime], [inputs], [status] and [layers] with\n"
         "# its default (sinewd --print-default-config). [rig] is required:\n\n"
         "[rig]\nbuiltin = \"arm\"  # \"arm\" | \"hand\", or blob = \"FILE.rig\" (compiled by rigc)\n";
  for (const std::string_view table : kTables) {
    out << "\n[" << table << "]\n";
    for (const DaemonKey& k : kKeys)
      if (k.table == table) out << k.key << " = " << k.default_toml << "  # " << k.doc << "\n";
  }
  DaemonConfig defaults;
  layers_text(defaults.layers, out);
  types_text(out);
  return out.str();
}

std::string resolved_config_text(const DaemonConfig& c) {
  std::ostringstream out;
  out << "[rig]\n"
      << (c.rig_blob.empty() ? "builtin = " + quoted(c.rig_builtin) : "blob = " + quoted(c.rig_blob)) << "\n";
  for (const std::string_view table : kTables) {
    out << "\n[" << table << "]\n";
    for (const DaemonKey& k : kKeys)
      if (k.table == table) out << k.key << " = " << k.value(c) << "\n";
  }
  layers_text(c.layers, out);
  for (const SourceConfig& s : c.sources) entry_text("[[source]]", s.table, out);
  for (const SinkConfig& s : c.sinks) entry_text("[[sink]]", s.table, out);
  return out.str();
}

}  // namespace sinew::firmware
