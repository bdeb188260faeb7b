// The simulated rig's quadrature encoders on a simulated GPIO chip: each
// configured encoder turns with its rig input's motion and drives its A/B
// (and index) lines with timestamped edges, exactly as the physical encoder
// wired as `hal::gpio::EncoderConfig` describes would. The firmware's
// GpioSource reads the same chip through the GpioChip interface, so the
// decoder, homing and fault handling run unchanged.
//
// The physical model: encoder i sits at count p = round((angle - offset) *
// counts_per_turn / 2^32), so count 0 is the configured offset angle. Every
// `update_ns` the motion's angle is sampled and the encoder steps from its
// previous count to the new one, one quadrature state per step, the steps
// spread evenly over the first three quarters of the interval (edges on one
// line never share a timestamp). The index line pulses (1 ns wide) when the
// count steps onto a multiple of counts_per_turn, once per joint turn.
// The decoder counts from wherever the encoder was at power-up, as a real
// incremental encoder does: without an index line the decoded angle is right
// only when the joint starts at `offset`; with one, from the first pulse.
//
// Faults (FaultPlan, kind kEncoderGlitch): in each update of the window both
// A and B flip at the same instant and flip back 1 us later (a spike on the
// encoder cable): two illegal transitions that the decoder must count
// without moving the count.
//
// Deterministic: edges depend only on the schedule, never on when advance()
// is called. No allocation after construction.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hal/gpio/gpio_source_config.hpp"
#include "hal/gpio/simulated_gpio.hpp"
#include "hal/sim/fault_plan.hpp"
#include "hal/sim/rig_motion.hpp"

namespace sinew::hal::sim {

struct SimulatedEncoderOptions {
  uint64_t update_ns = 1'000'000;  // how often the motion is sampled, 4 us .. 1 s
  FaultPlan faults;                // kEncoderGlitch windows (other kinds are ignored)
  size_t fifo_events = 16;         // the chip's event FIFO per line (the v1 kernel ABI's 16)
};

class SimulatedEncoders {
 public:
  // Each encoder's input must be a rotational input of the motion; the lines
  // must fit a chip of `line_count` lines and not be shared. False with a
  // message naming the offender.
  static bool validate(const std::vector<hal::gpio::EncoderConfig>& encoders, const SimulatedEncoderOptions& options,
                       const RigMotion& motion, const std::vector<bool>& rotation, uint32_t line_count,
                       std::string* error);
  // Sets every line to its level at the motion's start (before a source
  // requests them, so the decoders start from those levels).
  SimulatedEncoders(RigMotion motion, std::vector<hal::gpio::EncoderConfig> encoders, SimulatedEncoderOptions options,
                    uint32_t line_count, uint64_t start_ns);

  // The chip the encoders are wired to (hand wire().chip() to a GpioSource).
  hal::gpio::SimulatedGpio& wire() { return wire_; }
  // Plays every update at or before now_ns onto the lines.
  void advance(uint64_t now_ns);

  // Physical count of encoder i now, and the count its motion gives at t_ns
  // after the start (what the decoder must report once homed).
  int64_t position(size_t encoder) const { return position_[encoder]; }
  int64_t target_count(size_t encoder, uint64_t t_ns) const;
  uint64_t glitches() const { return glitches_; }
  uint64_t index_pulses() const { return index_pulses_; }

 private:
  void update(uint64_t t_ns, uint64_t from_ns, uint64_t to_ns);
  void drive(size_t encoder, uint64_t ts);  // sets A/B to position_'s state

  RigMotion motion_;
  std::vector<hal::gpio::EncoderConfig> encoders_;
  SimulatedEncoderOptions options_;
  hal::gpio::SimulatedGpio wire_;
  uint64_t start_ns_;
  uint64_t next_update_ = 1;  // update k plays the motion at k * update_ns
  std::vector<int64_t> position_;
  uint64_t glitches_ = 0;
  uint64_t index_pulses_ = 0;
};

}  // namespace sinew::hal::sim
