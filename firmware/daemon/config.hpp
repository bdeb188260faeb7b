// sinewd configuration (TOML). See firmware/config/default.toml for every key.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "firmware/runtime/realtime.hpp"
#include "firmware/runtime/tick_trigger.hpp"
#include "sim_core/pipeline/pipeline.hpp"

namespace sinew::firmware {

enum class RunMode { kLive, kReplay, kOffline };

// [loop] over_budget: what a live run does when the step measured at
// start-up takes more than step_budget of the period (step_fit.hpp).
enum class OverBudget { kWarn, kSlow, kRefuse };

struct SourceConfig {
  std::string type;  // a type of the source registry (sources.cpp): "trajectory", "can", "candump", ...
  std::string name;
  toml::table table;  // the whole [[source]] table, read by the backend's factory
};

struct SinkConfig {
  std::string type;  // a type of the sink registry (sinks.cpp): "log", "record", "udp"
  std::string name;
  toml::table table;
};

struct DaemonConfig {
  std::string rig_builtin;  // "arm" / "hand", or empty
  std::string rig_blob;     // path to a compiled rig (rigc -o), or empty
  uint32_t rate_hz = 1000;
  double duration_s = 0;  // 0: until SIGINT/SIGTERM
  double stats_interval_s = 1.0;
  RunMode mode = RunMode::kLive;
  // [loop] trigger: when a live tick starts (tick_trigger.hpp); the slot's
  // deadline is always the fallback. Offline and replay runs ignore it.
  TickTrigger trigger = TickTrigger::kPeriodic;
  double trigger_poll_us = 20.0;  // how often the sources are asked while a triggered tick waits
  // [loop] step_budget: the share of the period the step's p99, measured
  // before a live run starts, may take (0: not measured); over_budget: what
  // happens when it takes more.
  double step_budget = 0.5;
  OverBudget over_budget = OverBudget::kWarn;
  RealtimeOptions realtime;
  // [status]: the daemon's health as Modbus TCP registers for a PLC or HMI
  // (hal/modbus/status_server.hpp, docs/modbus.md "Status registers").
  struct Status {
    int32_t modbus_port = -1;               // -1: no server; 0: any free port (printed at start)
    std::string modbus_bind = "127.0.0.1";  // IPv4 address; "0.0.0.0": every interface
    int32_t modbus_max_clients = 4;
  } status;
  double timeout_factor = 1.5;      // stale after factor x expected period (CANopen style)
  double default_period_ms = 10.0;  // expected sample period when a source does not say
  double range_margin_deg = 10.0;   // accepted beyond a DOF limit (then clamped); further is a fault
  std::vector<SourceConfig> sources;
  std::vector<SinkConfig> sinks;
  // [layers]: which of the rig's compiled layers run (none by default: plain
  // skinning) and their run-time options. The keys are the stage table's
  // (sim_core/pipeline/stage_table.hpp); tick_hz is set from [loop] rate_hz
  // when the pipeline is built.
  pipeline::PipelineOptions layers = [] {
    pipeline::PipelineOptions o;
    o.stages = pipeline::StageSet::none();
    return o;
  }();
};

// Reads and validates a config file; errors name the file, line and key.
bool load_config(const std::string& path, DaemonConfig* out, std::string* error);
bool parse_config(std::string_view text, const std::string& origin, DaemonConfig* out, std::string* error);

}  // namespace sinew::firmware
