// Debounce of a contact input (limit switch) on kernel edge timestamps: a
// new level is accepted once it has held, with no further edge, for
// debounce_ns. Bounces shorter than that never reach the stable level. No
// timer is needed: an edge proves how long the previous level held, and at
// latch time the tick's timestamp does.
#pragma once

#include <cstdint>

namespace sinew::hal::gpio {

class Debouncer {
 public:
  void reset(bool level, uint64_t debounce_ns);
  // A raw logical edge at ts (non-decreasing across calls).
  void on_edge(bool level, uint64_t ts);
  // Accepts the raw level if it has held for debounce_ns by now_ns.
  // Returns true when the stable level changed.
  bool settle(uint64_t now_ns);

  bool stable() const { return stable_; }
  uint64_t changed_ns() const { return changed_ns_; }  // when the stable level last changed (edge ts + debounce)
  uint64_t bounces() const { return bounces_; }        // edges that interrupted a pending change
  uint64_t changes() const { return changes_; }

 private:
  bool stable_ = false;
  bool raw_ = false;
  uint64_t raw_since_ = 0;
  uint64_t debounce_ns_ = 0;
  uint64_t changed_ns_ = 0;
  uint64_t bounces_ = 0;
  uint64_t changes_ = 0;
};

}  // namespace sinew::hal::gpio
