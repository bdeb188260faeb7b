// Replay of a candump log (can-utils `candump -L` format) as a frame source,
// driven by the log's own timestamps: a frame logged at t is delivered as
// received at start_ns + (t - origin_ns). Nothing is read from disk after
// load(); drain() never allocates. Lines the parser rejected are kept as
// errors (reported at start-up, never silently dropped).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bus_state.hpp"
#include "candump_format.hpp"
#include "frame_source.hpp"

namespace sinew::hal::can {

struct CandumpReplayOptions {
  std::string path;
  std::string interface;    // replay only frames logged on this interface; empty: all
  bool has_origin = false;  // false: the first replayed frame's timestamp is the origin
  uint64_t origin_ns = 0;   // log time (ns) that maps to start_ns
};

class CandumpReplaySource final : public FrameSource {
 public:
  // Reads and parses the whole log; false with a message when the file cannot
  // be read or holds no frame for the interface.
  bool load(const CandumpReplayOptions& options, uint64_t start_ns, std::string* error);

  const char* name() const override { return "candump-replay"; }
  bool set_filters(std::span<const FrameId> ids, std::string* error) override;
  size_t drain(std::span<CanFrame> out, uint64_t now_ns) override;
  BusState bus_state() const override { return tracker_.state(); }
  const BusCounters& counters() const override { return tracker_.counters(); }

  size_t frame_count() const { return frames_.size(); }
  size_t remaining() const { return frames_.size() - next_; }
  const std::vector<CandumpError>& parse_errors() const { return errors_; }

 private:
  bool passes_filter(const CanFrame& frame) const;

  std::vector<CanFrame> frames_;  // in log order, timestamps mapped to the runtime clock
  std::vector<CandumpError> errors_;
  std::vector<FrameId> filters_;
  size_t next_ = 0;
  BusStateTracker tracker_;
};

}  // namespace sinew::hal::can
