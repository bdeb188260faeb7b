// sinewd configuration (TOML). See firmware/config/default.toml for every key.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "firmware/runtime/realtime.hpp"

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
  RealtimeOptions realtime;
  double timeout_factor = 1.5;      // stale after factor x expected period (CANopen style)
  double default_period_ms = 10.0;  // expected sample period when a source does not say
  double range_margin_deg = 10.0;   // accepted beyond a DOF limit (then clamped); further is a fault
  std::vector<SourceConfig> sources;
  std::vector<SinkConfig> sinks;
  bool layer_metaballs = false;       // [layers] metaballs: volume-preserving skin on the built-in arm
  int layer_anatomy_iterations = 0;   // [layers] anatomy: muscles + elastic skin, relaxations per tick (0 = off)
  bool layer_barnet = false;          // [layers] barnet: the elbow bar-net bulge on the built-in arm
  int layer_sph_particles = 0;        // [layers] sph_particles: SPH elastic elbow on the built-in arm (0 = off)
  double layer_sph_force_max_n = 40;  // [layers] sph_force_max_n: range of its elbow.force input, newtons
};

// Reads and validates a config file; errors name the file, line and key.
bool load_config(const std::string& path, DaemonConfig* out, std::string* error);
bool parse_config(std::string_view text, const std::string& origin, DaemonConfig* out, std::string* error);

}  // namespace sinew::firmware
