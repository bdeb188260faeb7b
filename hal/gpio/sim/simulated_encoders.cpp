#include "hal/gpio/sim/simulated_encoders.hpp"

#include <algorithm>

#include "hal/gpio/quadrature.hpp"

namespace sinew::hal::sim {

namespace {

using hal::gpio::EncoderConfig;
using hal::gpio::kNoLine;

using hal::gpio::kQuadratureForward;
constexpr uint64_t kGlitchWidthNs = 1000;

uint8_t state_of(const EncoderConfig& e, int64_t position) {
  // An inverted encoder's decoder counts B-leads-A as forward: the wire runs backwards.
  const int64_t raw = e.invert ? -position : position;
  return kQuadratureForward[static_cast<size_t>(((raw % 4) + 4) % 4)];
}

}  // namespace

bool SimulatedEncoders::validate(const std::vector<EncoderConfig>& encoders, const SimulatedEncoderOptions& options,
                                 const RigMotion& motion, const std::vector<bool>& rotation, uint32_t line_count,
                                 std::string* error) {
  if (options.update_ns < 10'000 || options.update_ns > 1'000'000'000)
    return *error = "simulated encoders: update period must be 10 us .. 1 s", false;
  if (encoders.empty()) return *error = "simulated encoders: no encoder configured", false;
  std::vector<bool> used(line_count, false);
  for (size_t i = 0; i < encoders.size(); ++i) {
    const EncoderConfig& e = encoders[i];
    const std::string which = "simulated encoder " + std::to_string(i);
    if (e.input >= motion.input_count() || e.input >= rotation.size())
      return *error = which + ": input " + std::to_string(e.input) + " is no rig input", false;
    if (!rotation[e.input])
      return *error = which + ": input " + std::to_string(e.input) + " is translational (encoders measure angles)",
             false;
    if (e.counts_per_turn < 1 || e.counts_per_turn > (1u << 30))
      return *error = which + ": counts_per_turn must be 1..2^30", false;
    const int64_t lines[3] = {e.line_a, e.line_b, e.line_index};
    for (const int64_t line : lines) {
      if (line == kNoLine) continue;
      if (line < 0 || line >= line_count)
        return *error = which + ": line " + std::to_string(line) + " is beyond the simulated chip's " +
                        std::to_string(line_count) + " lines",
               false;
      if (used[static_cast<size_t>(line)])
        return *error = which + ": line " + std::to_string(line) + " is used twice", false;
      used[static_cast<size_t>(line)] = true;
    }
  }
  return true;
}

SimulatedEncoders::SimulatedEncoders(RigMotion motion, std::vector<EncoderConfig> encoders,
                                     SimulatedEncoderOptions options, uint32_t line_count, uint64_t start_ns)
    : motion_(std::move(motion)),
      encoders_(std::move(encoders)),
      options_(std::move(options)),
      wire_(line_count, options_.fifo_events),
      start_ns_(start_ns),
      position_(encoders_.size(), 0) {
  for (size_t i = 0; i < encoders_.size(); ++i) {
    position_[i] = target_count(i, 0);
    drive(i, start_ns_);
    const EncoderConfig& e = encoders_[i];
    if (e.line_index != kNoLine) wire_.set_level(static_cast<uint32_t>(e.line_index), e.active_low, start_ns_);
  }
}

int64_t SimulatedEncoders::target_count(size_t encoder, uint64_t t_ns) const {
  const EncoderConfig& e = encoders_[encoder];
  // Signed turn fraction from the offset (wraps like every binary angle), in
  // 2^-32 turns; |diff| * cpt < 2^61, rounded half up.
  const auto diff =
      static_cast<int32_t>(static_cast<uint32_t>(motion_.value(e.input, t_ns)) - static_cast<uint32_t>(e.offset));
  return (int64_t{diff} * e.counts_per_turn + (int64_t{1} << 31)) >> 32;
}

void SimulatedEncoders::drive(size_t encoder, uint64_t ts) {
  const EncoderConfig& e = encoders_[encoder];
  const uint8_t ab = state_of(e, position_[encoder]);
  wire_.set_level(e.line_a, ((ab & 2u) != 0) != e.active_low, ts);
  wire_.set_level(e.line_b, ((ab & 1u) != 0) != e.active_low, ts);
}

void SimulatedEncoders::advance(uint64_t now_ns) {
  const uint64_t dt = options_.update_ns;
  while (now_ns >= start_ns_ && now_ns - start_ns_ >= next_update_ * dt) {
    const uint64_t t = next_update_ * dt;
    update(t, start_ns_ + t - dt, start_ns_ + t);
    ++next_update_;
  }
}

void SimulatedEncoders::update(uint64_t t_ns, uint64_t from_ns, uint64_t to_ns) {
  const uint64_t span = (to_ns - from_ns) / 4 * 3;
  // Steps at least 4 ns apart so an index pulse (ts + 1, ts + 2) fits between
  // them: the simulated encoder's top speed, far beyond any joint's.
  const auto max_steps = static_cast<int64_t>(span / 4);
  for (size_t i = 0; i < encoders_.size(); ++i) {
    const EncoderConfig& e = encoders_[i];
    const int64_t delta = std::clamp(target_count(i, t_ns) - position_[i], -max_steps, max_steps);
    const int64_t steps = delta < 0 ? -delta : delta;
    for (int64_t j = 1; j <= steps; ++j) {
      const uint64_t ts = from_ns + span * static_cast<uint64_t>(j) / static_cast<uint64_t>(steps + 1);
      position_[i] += delta < 0 ? -1 : 1;
      drive(i, ts);
      if (e.line_index != kNoLine && position_[i] % e.counts_per_turn == 0) {
        const auto index = static_cast<uint32_t>(e.line_index);
        wire_.set_level(index, !e.active_low, ts + 1);
        wire_.set_level(index, e.active_low, ts + 2);
        ++index_pulses_;
      }
    }
    if (options_.faults.active(FaultKind::kEncoderGlitch, t_ns - options_.update_ns, e.input) != nullptr) {
      // Both lines flip together and back: a spike on the cable, no motion.
      const uint64_t ts = from_ns + (to_ns - from_ns) / 8 * 7;
      const uint8_t ab = state_of(e, position_[i]);
      wire_.set_level(e.line_a, ((ab & 2u) == 0) != e.active_low, ts);
      wire_.set_level(e.line_b, ((ab & 1u) == 0) != e.active_low, ts);
      drive(i, ts + kGlitchWidthNs);
      ++glitches_;
    }
  }
}

}  // namespace sinew::hal::sim
