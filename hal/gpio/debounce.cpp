#include "debounce.hpp"

namespace sinew::hal::gpio {

void Debouncer::reset(bool level, uint64_t debounce_ns) {
  *this = Debouncer{};
  stable_ = raw_ = level;
  debounce_ns_ = debounce_ns;
}

bool Debouncer::settle(uint64_t now_ns) {
  if (raw_ == stable_ || now_ns < raw_since_ || now_ns - raw_since_ < debounce_ns_) return false;
  stable_ = raw_;
  changed_ns_ = raw_since_ + debounce_ns_;
  ++changes_;
  return true;
}

void Debouncer::on_edge(bool level, uint64_t ts) {
  settle(ts);                       // the previous level held until ts
  if (level == raw_) return;        // a lost opposite edge; nothing to time
  if (raw_ != stable_) ++bounces_;  // a pending change interrupted
  raw_ = level;
  raw_since_ = ts;
}

}  // namespace sinew::hal::gpio
