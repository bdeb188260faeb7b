// sinewd configuration (TOML). See firmware/config/default.toml for every key.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "firmware/runtime/realtime.hpp"
#include "firmware/runtime/tick_trigger.hpp"

namespace sinew::firmware {

enum class RunMode { kLive, kReplay, kOffline };

struct SourceConfig {
  std::string type;  // "trajectory", "can", "modbus", "gpio", "replay"
  std::string name;
  toml::table table;  // the whole [[source]] table, read by the backend's factory
};

struct SinkConfig {
  std::string type;  // "log", "udp", "can"
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
  RealtimeOptions realtime;
  double timeout_factor = 1.5;      // stale after factor x expected period (CANopen style)
  double default_period_ms = 10.0;  // expected sample period when a source does not say
  double range_margin_deg = 10.0;   // accepted beyond a DOF limit (then clamped); further is a fault
  std::vector<SourceConfig> sources;
  std::vector<SinkConfig> sinks;
  // [layers]: which of the rig's compiled layers run (all off by default).
  bool layer_sph = false;                 // SPH elastic joints with the Tresca yield (docs/sph.md)
  bool layer_metaballs = false;           // volume-preserving metaballs skin (docs/metaballs.md)
  bool layer_barnet = false;              // force-density bar-nets (docs/barnet.md)
  bool layer_anatomy = false;             // muscles + elastic skin (docs/anatomy.md)
  bool layer_tresca = true;               // the SPH yield condition, eqs. (3)-(4)
  bool layer_sph_joint_measured = false;  // [layers] sph_joint = "measured": the sensors' angles are the truth
  int layer_skin_iterations = 0;          // elastic-skin relaxations per tick; 0: the rig's
  // The dynamic skin's cap on its anchors' acceleration, m/s^2; 0: none
  // (pipeline::PipelineOptions::skin_max_anchor_acceleration).
  int layer_skin_max_anchor_acceleration = 500;
};

// Reads and validates a config file; errors name the file, line and key.
bool load_config(const std::string& path, DaemonConfig* out, std::string* error);
bool parse_config(std::string_view text, const std::string& origin, DaemonConfig* out, std::string* error);

}  // namespace sinew::firmware
