// Per-line event queues of fixed capacity, merged oldest-first on the way
// out. The libgpiod v1 backend stages what it reads from each line's event
// fd here (one fd per line in the v1 ABI); the simulated twin uses them as
// the kernel's per-line FIFOs. Storage is allocated once, at request time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "line_io.hpp"

namespace sinew::hal::gpio {

class LineQueues {
 public:
  void init(size_t lines, size_t capacity);
  size_t space(size_t line) const { return capacity_ - count_[line]; }
  bool empty() const;
  // False (event dropped) when the line's queue is full.
  bool push(size_t line, const LineEvent& event);
  // Pops up to out.size() events, oldest timestamp first across lines (ties:
  // lower line index first).
  size_t pop_oldest(std::span<LineEvent> out);

 private:
  size_t capacity_ = 0;
  std::vector<LineEvent> ring_;  // lines * capacity
  std::vector<size_t> head_;
  std::vector<size_t> count_;
};

}  // namespace sinew::hal::gpio
