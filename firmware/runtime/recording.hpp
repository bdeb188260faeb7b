// A recording: the daemon's inputs, not its outputs. The outputs are a
// deterministic function of the rig, the pipeline options and the inputs as
// applied each tick, so a run is recorded as a frame log without vertices
// (per tick: the applied input values and their status bits, 32 + 5 x inputs
// bytes) whose header carries this description of the run. `sinew-log
// render` re-simulates the full frames from it, bit for bit.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "hal/common/input_source.hpp"
#include "hal/common/pose_frame.hpp"
#include "sim_core/pipeline/pipeline.hpp"

namespace sinew::firmware {

struct RunDescription {
  uint64_t rig_xxh64 = 0;  // XXH64 (seed 0) of the rig blob's bytes
  uint64_t rig_bytes = 0;
  pipeline::PipelineOptions options;  // as the run used them (tick_hz set)
};

// XXH64 of a blob, as a recording names its rig.
uint64_t rig_blob_hash(const uint8_t* blob, size_t size);

// "sinew-recording 1" then one "key = value" line per field.
std::string encode_run_description(const RunDescription& run);
// False with a message naming the line or the key that is wrong or missing.
bool parse_run_description(std::string_view text, RunDescription* out, std::string* error);

// The recording sink: hands the frame, without its vertices, to `log`.
// Per tick no allocation: the frame is a copy of pointers.
template <typename Log>
class RecordingSink final : public hal::OutputSink {
 public:
  RecordingSink(std::unique_ptr<Log> log, std::string label) : log_(std::move(log)), label_(std::move(label)) {}
  const char* name() const override { return label_.c_str(); }
  bool write(const hal::PoseFrame& frame) override {
    hal::PoseFrame inputs_only = frame;
    inputs_only.vertex_count = 0;
    for (int c = 0; c < 3; ++c) inputs_only.position[c] = inputs_only.normal[c] = nullptr;
    return log_->write(inputs_only);
  }
  void flush() override { log_->flush(); }
  std::string status_line() const override { return "recording: " + log_->status_line(); }

 private:
  std::unique_ptr<Log> log_;
  std::string label_;
};

}  // namespace sinew::firmware
