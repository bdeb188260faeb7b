#include "recording.hpp"

#include <xxhash.h>

#include <charconv>
#include <cinttypes>
#include <cstdio>

namespace sinew::firmware {

namespace {

constexpr std::string_view kFirstLine = "sinew-recording 1";

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

template <typename T>
bool parse_uint(std::string_view v, int base, T* out) {
  const auto r = std::from_chars(v.data(), v.data() + v.size(), *out, base);
  return r.ec == std::errc() && r.ptr == v.data() + v.size();
}

bool parse_bool(std::string_view v, bool* out) {
  if (v == "true") return *out = true, true;
  if (v == "false") return *out = false, true;
  return false;
}

}  // namespace

uint64_t rig_blob_hash(const uint8_t* blob, size_t size) { return XXH64(blob, size, 0); }

std::string encode_run_description(const RunDescription& run) {
  char buf[512];
  const pipeline::PipelineOptions& o = run.options;
  std::snprintf(buf, sizeof buf,
                "%.*s\nrig_xxh64 = %016" PRIx64 "\nrig_bytes = %" PRIu64
                "\ntick_hz = %u\nsph = %s\nmetaballs = %s\nbarnet = %s\nanatomy = %s\ntresca = %s\n"
                "skin_iterations = %u\n",
                static_cast<int>(kFirstLine.size()), kFirstLine.data(), run.rig_xxh64, run.rig_bytes, o.tick_hz,
                o.sph ? "true" : "false", o.metaballs ? "true" : "false", o.barnet ? "true" : "false",
                o.anatomy ? "true" : "false", o.tresca ? "true" : "false", o.skin_iterations);
  // Written only when set, so that the description of a simulated-joint run
  // (and every recording made before the key existed) stays as it was.
  std::string out = std::string(buf) + (o.sph_joint_measured ? "sph_joint_measured = true\n" : "");
  // Likewise the dynamic skin's anchor-acceleration cap, when not the default.
  if (o.skin_max_anchor_acceleration != pipeline::PipelineOptions{}.skin_max_anchor_acceleration)
    out += "skin_max_anchor_acceleration = " + std::to_string(o.skin_max_anchor_acceleration) + "\n";
  return out;
}

bool parse_run_description(std::string_view text, RunDescription* out, std::string* error) {
  RunDescription run;
  unsigned seen = 0;  // one bit per key
  size_t line_no = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    const std::string_view line = trim(text.substr(0, end));
    text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
    ++line_no;
    if (line_no == 1) {
      if (line != kFirstLine)
        return *error = "not a sinew recording description (first line '" + std::string(line) + "')", false;
      continue;
    }
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos)
      return *error = "recording description line " + std::to_string(line_no) + ": no '='", false;
    const std::string_view key = trim(line.substr(0, eq)), value = trim(line.substr(eq + 1));
    pipeline::PipelineOptions& o = run.options;
    struct Flag {
      std::string_view key;
      bool* field;
    };
    const Flag flags[] = {
        {"sph", &o.sph},       {"metaballs", &o.metaballs},
        {"barnet", &o.barnet}, {"anatomy", &o.anatomy},
        {"tresca", &o.tresca}, {"sph_joint_measured", &o.sph_joint_measured}};  // optional: bit 9 is not required
    bool ok = false;
    unsigned bit = 0;
    if (key == "rig_xxh64") {
      ok = value.size() == 16 && parse_uint(value, 16, &run.rig_xxh64), bit = 1u << 0;
    } else if (key == "rig_bytes") {
      ok = parse_uint(value, 10, &run.rig_bytes), bit = 1u << 1;
    } else if (key == "tick_hz") {
      ok = parse_uint(value, 10, &o.tick_hz) && o.tick_hz > 0, bit = 1u << 2;
    } else if (key == "skin_iterations") {
      ok = parse_uint(value, 10, &o.skin_iterations), bit = 1u << 3;
    } else if (key == "skin_max_anchor_acceleration") {  // optional, as sph_joint_measured
      ok = parse_uint(value, 10, &o.skin_max_anchor_acceleration) && o.skin_max_anchor_acceleration <= 32767,
      bit = 1u << 10;
    } else {
      for (size_t i = 0; i < std::size(flags); ++i)
        if (key == flags[i].key) ok = parse_bool(value, flags[i].field), bit = 1u << (4 + i);
      if (bit == 0)
        return *error =
                   "recording description line " + std::to_string(line_no) + ": unknown key '" + std::string(key) + "'",
               false;
    }
    if (!ok)
      return *error = "recording description line " + std::to_string(line_no) + ": bad value for " + std::string(key),
             false;
    seen |= bit;
  }
  if (line_no == 0) return *error = "empty recording description", false;
  constexpr unsigned kRequired = (1u << 9) - 1;  // every key but sph_joint_measured
  if ((seen & kRequired) != kRequired)
    return *error = "recording description lacks a key (rig, tick rate and layers)", false;
  *out = run;
  return true;
}

}  // namespace sinew::firmware
