// Checks a frame log (docs/frame-formats.md) from end to end, beyond what the
// reader's per-record checksums cover: the stream's own consistency. Within a
// run ticks increase (a gap is skipped ticks, reported, not an error) and
// timestamps do not go backwards. A tick lower than the one before starts a
// new run (the daemon appends to an existing log after a restart); the same
// tick twice in a row is an error. Host side; allocates.
#pragma once

#include <cstdint>
#include <string>

#include "hal/output/frame_log_reader.hpp"

namespace sinew::log_tool {

struct LogCheck {
  hal::output::FrameShape shape;
  std::string metadata;     // a recording's run description (empty for a frame log)
  bool compressed = false;  // zstd-compressed records (docs/frame-formats.md)
  uint64_t frames = 0;
  uint64_t first_tick = 0, last_tick = 0;
  uint64_t first_ns = 0, last_ns = 0;
  uint64_t tick_gaps = 0;               // places where ticks jump by more than one
  uint64_t missing_ticks = 0;           // ticks absent in those gaps
  uint64_t runs = 0;                    // segments whose ticks increase; a new one starts at a lower tick
  uint64_t tick_disorder = 0;           // a tick repeated (an error)
  uint64_t time_disorder = 0;           // timestamps that went backwards within a run (an error)
  uint64_t frames_with_status[4] = {};  // frames with an input clamped, stale, rejected, yielded
  uint64_t content_hash = 0;            // XXH64 over the records' payloads in order
  bool clean_end = false;               // the file ends exactly after its last record
  std::string stop;                     // where and why reading stopped, when not clean

  // True when the log is intact and consistent.
  bool ok() const { return clean_end && tick_disorder == 0 && time_disorder == 0; }
};

// False (with a message naming the file) only when the file cannot be
// opened or its header is wrong; damage after the header is reported in
// the result.
bool check_log(const std::string& path, LogCheck* out, std::string* error);

// Several lines: the shape, the span of ticks and time, the gaps and flags,
// and the verdict.
std::string describe(const std::string& path, const LogCheck& c);

}  // namespace sinew::log_tool
