#include "log_check.hpp"

#include <xxhash.h>

#include <cinttypes>
#include <cstdio>

namespace sinew::log_tool {

namespace {

template <typename T>
void hash_values(XXH64_state_t* state, const std::vector<T>& values) {
  if (!values.empty()) XXH64_update(state, values.data(), values.size() * sizeof(T));
}

void hash_pose(XXH64_state_t* state, const hal::output::DecodedPose& p) {
  XXH64_update(state, &p.tick, sizeof p.tick);
  XXH64_update(state, &p.timestamp_ns, sizeof p.timestamp_ns);
  for (int c = 0; c < 3; ++c) hash_values(state, p.position[c]);
  for (int c = 0; c < 3; ++c) hash_values(state, p.normal[c]);
  hash_values(state, p.input_value);
  hash_values(state, p.input_status);
}

}  // namespace

bool check_log(const std::string& path, LogCheck* out, std::string* error) {
  hal::output::FrameLogReader reader;
  if (!reader.open(path, error)) return false;
  LogCheck c;
  c.shape = reader.shape();
  c.metadata = reader.metadata();
  c.compressed = reader.compressed();
  XXH64_state_t* state = XXH64_createState();
  XXH64_reset(state, 0);
  hal::output::DecodedPose pose;
  while (reader.next(&pose)) {
    if (c.frames == 0) {
      c.first_tick = pose.tick;
      c.first_ns = pose.timestamp_ns;
      c.runs = 1;
    } else if (pose.tick < c.last_tick) {
      ++c.runs;  // a restart appended to the log
    } else {
      if (pose.tick == c.last_tick) {
        ++c.tick_disorder;
      } else if (pose.tick > c.last_tick + 1) {
        ++c.tick_gaps;
        c.missing_ticks += pose.tick - c.last_tick - 1;
      }
      if (pose.timestamp_ns < c.last_ns) ++c.time_disorder;
    }
    c.last_tick = pose.tick;
    c.last_ns = pose.timestamp_ns;
    uint8_t any = 0;
    for (uint8_t s : pose.input_status) any = static_cast<uint8_t>(any | s);
    for (int bit = 0; bit < 4; ++bit)
      if (any & (1u << bit)) ++c.frames_with_status[bit];
    hash_pose(state, pose);
    ++c.frames;
  }
  c.content_hash = XXH64_digest(state);
  XXH64_freeState(state);
  c.clean_end = reader.clean_end();
  if (!c.clean_end) c.stop = reader.stop_message();
  *out = c;
  return true;
}

std::string describe(const std::string& path, const LogCheck& c) {
  char buf[1024];
  std::string s;
  std::snprintf(buf, sizeof buf, "%s: %u vertices%s, %u inputs, one rig unit = 2^%d m%s\n", path.c_str(),
                c.shape.vertex_count, c.shape.normals ? " with normals" : "", c.shape.input_count,
                c.shape.length_exponent, c.compressed ? "; records zstd-compressed" : "");
  s += buf;
  if (!c.metadata.empty()) {
    // A recording: say so, and which run it holds (sinew-log render regenerates its frames).
    s += "  a recording (inputs only) of the run:\n";
    size_t at = 0;
    while (at < c.metadata.size()) {
      const size_t end = c.metadata.find('\n', at);
      s += "    " + c.metadata.substr(at, end == std::string::npos ? std::string::npos : end - at) + "\n";
      at = end == std::string::npos ? c.metadata.size() : end + 1;
    }
  }
  if (c.frames == 0) {
    s += "  no frames\n";
  } else {
    std::snprintf(buf, sizeof buf,
                  "  %" PRIu64 " frames, ticks %" PRIu64 "..%" PRIu64 ", %.6f s; %" PRIu64 " gaps (%" PRIu64
                  " ticks missing)\n",
                  c.frames, c.first_tick, c.last_tick, static_cast<double>(c.last_ns - c.first_ns) * 1e-9, c.tick_gaps,
                  c.missing_ticks);
    if (c.runs > 1)
      std::snprintf(buf, sizeof buf,
                    "  %" PRIu64 " frames in %" PRIu64 " runs (appended after restarts); %" PRIu64 " gaps (%" PRIu64
                    " ticks missing)\n",
                    c.frames, c.runs, c.tick_gaps, c.missing_ticks);
    s += buf;
    std::snprintf(buf, sizeof buf,
                  "  frames with an input clamped %" PRIu64 ", stale %" PRIu64 ", rejected %" PRIu64
                  ", yielded %" PRIu64 "\n",
                  c.frames_with_status[0], c.frames_with_status[1], c.frames_with_status[2], c.frames_with_status[3]);
    s += buf;
    std::snprintf(buf, sizeof buf, "  content xxh64 %016" PRIx64 "\n", c.content_hash);
    s += buf;
  }
  if (c.tick_disorder > 0)
    s += "  error: " + std::to_string(c.tick_disorder) + " frames repeating the tick before them\n";
  if (c.time_disorder > 0)
    s += "  error: " + std::to_string(c.time_disorder) + " frames whose timestamp went backwards within a run\n";
  if (!c.clean_end) s += "  damaged: " + c.stop + " (the frames above are intact)\n";
  s += c.ok() ? "ok\n" : "FAILED\n";
  return s;
}

}  // namespace sinew::log_tool
