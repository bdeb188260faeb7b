// The viewer's two feeds: a live UDP stream and a replayed frame log. Each
// decodes frames, steps the shadow pipeline with their inputs and sends the
// latest frame to the pages at most ~30 times a second (the stream may run
// at 1 kHz; a page draws at its display's rate).
#pragma once

#include <csignal>
#include <cstdint>
#include <string>
#include <vector>

#include "hal/output/pose_decode.hpp"
#include "shadow_pipeline.hpp"
#include "view_rig.hpp"
#include "web_server.hpp"

namespace sinew::view {

struct ViewContext {
  const ViewRig* rig = nullptr;
  WebServer* server = nullptr;
  pipeline::PipelineOptions options;
  uint32_t tick_hz = 0;  // the tick budget's rate; 0: estimated from the frames' timestamps
  volatile std::sig_atomic_t* stop = nullptr;
};

// Both return the exit status: 0 when stopped by a signal, 1 on an error.
int run_live(const ViewContext& ctx, const std::string& bind_address, uint16_t udp_port);
int run_replay(const ViewContext& ctx, const std::string& log_path);

// Marks the inputs whose value equals the previous tick's frame (counters's
// input_held); `previous` keeps the last frame's values.
void mark_held_inputs(const hal::output::DecodedPose& pose, const hal::output::DecodedPose* previous,
                      std::vector<uint8_t>* held);

// The tick period the frames show: (timestamp difference) / (tick difference)
// between consecutive frames, the smallest seen (a skipped tick's gap and a
// late frame only lengthen it).
class PeriodEstimate {
 public:
  void add(const hal::output::DecodedPose& pose);
  uint64_t period_ns(uint32_t tick_hz_override) const;

 private:
  bool have_ = false;
  uint64_t last_tick_ = 0, last_ns_ = 0, best_ns_ = 0;
};

}  // namespace sinew::view
