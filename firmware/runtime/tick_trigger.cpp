#include "tick_trigger.hpp"

#include <cerrno>
#include <ctime>

#include "hal/common/monotonic_clock.hpp"

namespace sinew::firmware {

const char* tick_trigger_name(TickTrigger t) {
  switch (t) {
    case TickTrigger::kPeriodic:
      return "periodic";
    case TickTrigger::kInputs:
      return "inputs";
    case TickTrigger::kSync:
      return "sync";
  }
  return "unknown";
}

uint8_t trigger_signal(TickTrigger t) {
  switch (t) {
    case TickTrigger::kPeriodic:
      return hal::kSignalsNothing;
    case TickTrigger::kInputs:
      return hal::kSignalsComplete;
    case TickTrigger::kSync:
      return hal::kSignalsSync;
  }
  return hal::kSignalsNothing;
}

bool tick_ready(TickTrigger trigger, std::span<const std::unique_ptr<InputSource>> sources, uint64_t now_ns) {
  if (trigger == TickTrigger::kPeriodic) return false;
  const uint8_t signal = trigger_signal(trigger);
  bool asked = false;
  for (const auto& source : sources) {
    if ((source->arrival_signals() & signal) == 0) continue;
    const hal::Arrival a = source->arrival(now_ns);
    if (trigger == TickTrigger::kSync) {
      if (a.sync) return true;
      continue;
    }
    if (!a.complete) return false;  // one incomplete source holds the tick until its deadline
    asked = true;
  }
  return asked;
}

uint64_t MonotonicWaitClock::now_ns() { return hal::monotonic_ns(); }

void MonotonicWaitClock::sleep_until_ns(uint64_t t) {
  const timespec deadline{static_cast<time_t>(t / 1000000000u), static_cast<long>(t % 1000000000u)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

TriggeredTick TriggeredTickClock::wait_next(std::span<const std::unique_ptr<InputSource>> sources, WaitClock& clock) {
  uint64_t now = clock.now_ns();
  if (now > next_ + period_) {  // over a whole period behind: skip, don't burst
    const uint64_t behind = (now - next_) / period_;
    skipped_ += behind;
    next_ += behind * period_;
  }
  // A slot's window opens at the previous slot's deadline: one tick per slot.
  const uint64_t open = next_ > period_ ? next_ - period_ : 0;
  TriggeredTick tick{next_, next_, false};
  while (now < next_) {
    if (now >= open && tick_ready(trigger_, sources, now)) {
      tick.time_ns = now;
      tick.triggered = true;
      break;
    }
    uint64_t wake = now < open ? open : now + poll_;
    if (wake > next_ || trigger_ == TickTrigger::kPeriodic) wake = next_;
    clock.sleep_until_ns(wake);
    now = clock.now_ns();
  }
  // The fallback runs at the deadline's nominal time, as a periodic tick
  // does: same latch, same health flags.
  ++(tick.triggered ? triggered_ : fallback_);
  next_ += period_;
  return tick;
}

}  // namespace sinew::firmware
