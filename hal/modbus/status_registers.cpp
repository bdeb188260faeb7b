#include "status_registers.hpp"

#include <algorithm>

namespace sinew::hal::modbus {

namespace {

uint16_t word(uint64_t v, int shift) { return static_cast<uint16_t>((v >> shift) & 0xFFFFu); }
uint16_t saturate16(uint64_t v) { return static_cast<uint16_t>(std::min<uint64_t>(v, 0xFFFFu)); }

}  // namespace

uint16_t source_state_code(SourceState s) {
  switch (s) {
    case SourceState::kOk:
      return 0;
    case SourceState::kDegraded:
      return 1;
    case SourceState::kDown:
      return 2;
  }
  return 2;
}

void encode_status(const StatusUpdate& update, uint16_t heartbeat, std::span<uint16_t> image) {
  std::fill(image.begin(), image.end(), uint16_t{0});
  if (image.size() < status_reg::kInputStatus) return;
  namespace r = status_reg;
  image[r::kLayoutVersion] = kStatusLayout;
  image[r::kHeartbeat] = heartbeat;
  for (size_t i = 0; i < 4; ++i) image[r::kTick + i] = word(update.tick, static_cast<int>(48 - 16 * i));
  const uint64_t step_us = std::min<uint64_t>(update.last_step_ns / 1000u, 0xFFFFFFFFu);
  image[r::kLastStepUs] = word(step_us, 16);
  image[r::kLastStepUs + 1] = word(step_us, 0);
  image[r::kStaleCount] = saturate16(update.stale_count);

  const size_t inputs = std::min(update.input_status.size(), image.size() - r::kInputStatus);
  image[r::kInputCount] = saturate16(inputs);
  for (size_t i = 0; i < inputs; ++i) image[r::kInputStatus + i] = update.input_status[i];

  const size_t sources = std::min(update.source_states.size(), kMaxStatusSources);
  image[r::kSourceCount] = saturate16(sources);
  uint16_t down = 0, degraded = 0;
  for (size_t i = 0; i < sources; ++i) {
    const uint16_t code = source_state_code(update.source_states[i]);
    image[r::kSourceState + i] = code;
    down = static_cast<uint16_t>(down + (code == 2 ? 1 : 0));
    degraded = static_cast<uint16_t>(degraded + (code == 1 ? 1 : 0));
  }
  image[r::kSourcesDown] = down;
  image[r::kSourcesDegraded] = degraded;
}

}  // namespace sinew::hal::modbus
