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

#include "firmware/sinks/inputs_only_sink.hpp"
#include "hal/common/output_sink.hpp"
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

// The recording sink: the frame without its vertices to the sink it wraps
// (a frame log of no vertices, behind its I/O thread's ring).
class RecordingSink final : public InputsOnlySink {
 public:
  explicit RecordingSink(std::unique_ptr<hal::OutputSink> inner) : InputsOnlySink(std::move(inner), "recording") {}
};

}  // namespace sinew::firmware
