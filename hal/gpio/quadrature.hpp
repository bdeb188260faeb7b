// 4x quadrature decoding from A/B edge events: every edge of either line is
// one count. The lines are sampled as a state AB = (A << 1) | B and each
// state change is looked up in a 16-entry transition table (the classic
// Gray-code decoder): forward 00 -> 10 -> 11 -> 01 -> 00, backward the
// reverse. A change of both lines at once cannot be given a direction: it is
// counted as illegal and the decoder resynchronises to the observed state
// without moving the count.
//
// When do both lines change "at once"? Edges are grouped into one sample when
// they fall within `window_ns` of the first edge of the sample (0: only edges
// with the same kernel timestamp). An encoder moving faster than the window
// resolves, or a glitch on one line while the other moves, then shows up as
// an illegal transition instead of a silent miscount.
#pragma once

#include <cstdint>

namespace sinew::hal::gpio {

// The AB states (A << 1 | B) of successive forward positions; position p is
// in state kQuadratureForward[p mod 4].
inline constexpr uint8_t kQuadratureForward[4] = {0b00, 0b10, 0b11, 0b01};

// Direction of one state change: +1 forward, -1 backward, 0 no change,
// kIllegalStep for a both-lines change.
inline constexpr int8_t kIllegalStep = 2;
int8_t quadrature_step(uint8_t from_ab, uint8_t to_ab);

struct QuadratureCounters {
  uint64_t edges = 0;              // A/B edges applied
  uint64_t illegal = 0;            // both-lines changes (count not moved)
  uint64_t missed_edges = 0;       // an edge to the level the line already had: one was lost (kernel queue overflow)
  uint64_t index_pulses = 0;       // active index edges seen
  uint64_t index_corrections = 0;  // index pulses that found the count off its home value (after the first homing)
  uint64_t resyncs = 0;            // the lines' read-back levels differed from the decoded state (events lost)
};

class QuadratureDecoder {
 public:
  // a, b: logical levels at request time. window_ns: see above.
  void reset(bool a, bool b, uint64_t window_ns);

  // One logical edge on A (line 0) or B (line 1) at kernel time ts (ts
  // non-decreasing across calls).
  void on_edge(int line, bool level, uint64_t ts);
  // Commits the pending sample if its window has closed by now_ns (ts of the
  // window's first edge + window_ns <= now_ns).
  void settle(uint64_t now_ns);
  // Index pulse at ts: commits the pending sample, then sets the count to
  // home_count on the first pulse (and on every pulse when every_pulse).
  void on_index(uint64_t ts, int64_t home_count, bool every_pulse);
  // After events may have been lost: commits the pending sample and adopts
  // the lines' actual levels without moving the count.
  void resync(bool a, bool b);

  int64_t count() const { return count_; }
  bool homed() const { return homed_; }
  uint8_t state() const { return state_; }
  const QuadratureCounters& counters() const { return counters_; }

 private:
  void commit();

  int64_t count_ = 0;
  uint8_t state_ = 0;  // committed AB
  uint8_t next_ = 0;   // AB after the pending edges
  bool pending_ = false;
  uint64_t pending_since_ = 0;
  uint64_t window_ns_ = 0;
  bool homed_ = false;
  QuadratureCounters counters_;
};

// Binary angle (2^32 per turn) of `count` with `counts_per_turn` counts per
// joint turn (1 .. 2^30), plus `offset` (binary angle). Rounded half up;
// wraps every turn like every binary angle.
int32_t counts_to_angle(int64_t count, uint32_t counts_per_turn, int32_t offset);

}  // namespace sinew::hal::gpio
