// When a live tick starts. Periodic: at its slot's deadline (tick_clock.hpp).
// Inputs: as soon as every source that can tell reports a complete new sample
// set; sync: as soon as a source reports its sync event. Either way the
// slot's deadline is the fallback, so a silent input never stalls the loop:
// the tick then runs at the deadline, on the held inputs, exactly as a
// periodic one. A slot runs at most one tick, in (previous deadline,
// deadline]: the rate never exceeds rate_hz and frame numbers stay slot
// numbers. Offline and replay runs keep their nominal tick times; the trigger
// only moves live ticks earlier. No allocation after construction.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "io.hpp"

namespace sinew::firmware {

enum class TickTrigger : uint8_t {
  kPeriodic,  // every slot at its deadline
  kInputs,    // when every source that signals completeness has a new set
  kSync,      // on a source's sync event (a CAN sync frame, a GPIO sync edge)
};

const char* tick_trigger_name(TickTrigger t);

// The source bit (hal::ArrivalSignal) a trigger needs: at least one source
// must have it, or the trigger could never fire.
uint8_t trigger_signal(TickTrigger t);

// Whether the sources let a tick start at now_ns. Inputs: every source with
// kSignalsComplete reports complete (sources without it are sampled as they
// are). Sync: some source with kSignalsSync reports sync. Periodic: never.
bool tick_ready(TickTrigger trigger, std::span<const std::unique_ptr<InputSource>> sources, uint64_t now_ns);

// The time base of the wait, injectable so tests run on simulated time.
class WaitClock {
 public:
  virtual ~WaitClock() = default;
  virtual uint64_t now_ns() = 0;                // CLOCK_MONOTONIC
  virtual void sleep_until_ns(uint64_t t) = 0;  // absolute; returns at or after t
};

// CLOCK_MONOTONIC with clock_nanosleep(TIMER_ABSTIME).
class MonotonicWaitClock final : public WaitClock {
 public:
  uint64_t now_ns() override;
  void sleep_until_ns(uint64_t t) override;
};

struct TriggeredTick {
  uint64_t time_ns = 0;      // latch and frame time: when the trigger fired, else the deadline
  uint64_t deadline_ns = 0;  // the slot's deadline: start + (slot + 1) x period
  bool triggered = false;    // false: the deadline fallback
};

class TriggeredTickClock {
 public:
  // first_deadline_ns: the first slot's deadline. poll_ns: how often the
  // sources are asked while waiting (> 0).
  TriggeredTickClock(TickTrigger trigger, uint64_t period_ns, uint64_t first_deadline_ns, uint64_t poll_ns)
      : trigger_(trigger), period_(period_ns), next_(first_deadline_ns), poll_(poll_ns > 0 ? poll_ns : 1) {}
  // Waits for the trigger or the next deadline, whichever comes first. Over
  // a whole period behind, the schedule skips ahead as TickClock's does.
  TriggeredTick wait_next(std::span<const std::unique_ptr<InputSource>> sources, WaitClock& clock);
  // True if the step that just ran finished after the following deadline.
  bool finished_late(uint64_t now_ns) const { return now_ns > next_; }
  uint64_t skipped_ticks() const { return skipped_; }
  uint64_t triggered_ticks() const { return triggered_; }
  uint64_t fallback_ticks() const { return fallback_; }

 private:
  TickTrigger trigger_;
  uint64_t period_;
  uint64_t next_;
  uint64_t poll_;
  uint64_t skipped_ = 0;
  uint64_t triggered_ = 0;
  uint64_t fallback_ = 0;
};

}  // namespace sinew::firmware
