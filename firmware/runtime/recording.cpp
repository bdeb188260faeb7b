#include "recording.hpp"

#include <xxhash.h>

#include <charconv>
#include <cinttypes>
#include <cstdio>

#include "sim_core/pipeline/stage_table.hpp"

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

// The description's keys after the rig's and the rate: one flag per layer,
// then the layers' options, both from the stage table, in its order.
std::string encode_run_description(const RunDescription& run) {
  const pipeline::PipelineOptions& o = run.options;
  const pipeline::PipelineOptions defaults;
  char head[160];
  std::snprintf(head, sizeof head, "%.*s\nrig_xxh64 = %016" PRIx64 "\nrig_bytes = %" PRIu64 "\ntick_hz = %u\n",
                static_cast<int>(kFirstLine.size()), kFirstLine.data(), run.rig_xxh64, run.rig_bytes, o.tick_hz);
  std::string out = head;
  for (const pipeline::StageInfo& s : pipeline::kStages)
    if (s.stage != pipeline::Stage::kSkinning)
      out += std::string(s.name) + " = " + (o.stages.has(s.stage) ? "true" : "false") + "\n";
  // An option added after the format was fixed is written only when it is
  // not the default, so the description of a run that leaves it (and every
  // recording made before it existed) stays as it was.
  for (const pipeline::StageOption& option : pipeline::kStageOptions) {
    std::string value;
    bool is_default = false;
    const uint32_t v = pipeline::option_value(option, o);
    if (option.kind == pipeline::OptionKind::kNumber)
      value = std::to_string(v);
    else
      value = v != 0 ? "true" : "false";
    is_default = v == pipeline::option_value(option, defaults);
    if (option.recorded_always || !is_default) out += std::string(option.recording_key) + " = " + value + "\n";
  }
  return out;
}

bool parse_run_description(std::string_view text, RunDescription* out, std::string* error) {
  RunDescription run;
  pipeline::PipelineOptions& o = run.options;
  // Keys by index: the rig's and the rate, the stages but skinning, the options.
  constexpr size_t kFixed = 3, kLayers = pipeline::kStageCount - 1;
  constexpr size_t kKeys = kFixed + kLayers + std::size(pipeline::kStageOptions);
  static_assert(kKeys <= 32);
  uint32_t required = (1u << (kFixed + kLayers)) - 1;
  for (size_t i = 0; i < std::size(pipeline::kStageOptions); ++i)
    if (pipeline::kStageOptions[i].recorded_always) required |= 1u << (kFixed + kLayers + i);
  uint32_t seen = 0;
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
    bool ok = false;
    size_t index = kKeys;
    if (key == "rig_xxh64") {
      ok = value.size() == 16 && parse_uint(value, 16, &run.rig_xxh64), index = 0;
    } else if (key == "rig_bytes") {
      ok = parse_uint(value, 10, &run.rig_bytes), index = 1;
    } else if (key == "tick_hz") {
      ok = parse_uint(value, 10, &o.tick_hz) && o.tick_hz > 0, index = 2;
    } else if (const pipeline::StageInfo* s = pipeline::find_stage(key.data(), key.size());
               s != nullptr && s->stage != pipeline::Stage::kSkinning) {
      bool on = false;
      ok = parse_bool(value, &on), index = kFixed + static_cast<size_t>(s->stage) - 1;
      o.stages.set(s->stage, on);
    } else {
      for (size_t i = 0; i < std::size(pipeline::kStageOptions); ++i) {
        const pipeline::StageOption& option = pipeline::kStageOptions[i];
        if (key != option.recording_key) continue;
        index = kFixed + kLayers + i;
        if (option.kind == pipeline::OptionKind::kNumber)
          ok = parse_uint(value, 10, option.number(&o)) && *option.number(&o) >= option.min &&
               *option.number(&o) <= option.max;
        else
          ok = parse_bool(value, option.flag(&o));
      }
      if (index == kKeys)
        return *error =
                   "recording description line " + std::to_string(line_no) + ": unknown key '" + std::string(key) + "'",
               false;
    }
    if (!ok)
      return *error = "recording description line " + std::to_string(line_no) + ": bad value for " + std::string(key),
             false;
    seen |= 1u << index;
  }
  if (line_no == 0) return *error = "empty recording description", false;
  if ((seen & required) != required)
    return *error = "recording description lacks a key (rig, tick rate and layers)", false;
  *out = run;
  return true;
}

}  // namespace sinew::firmware
