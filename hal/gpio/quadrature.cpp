#include "quadrature.hpp"

namespace sinew::hal::gpio {

namespace {

constexpr int8_t X = kIllegalStep;
// kStep[from][to], states AB = (A << 1) | B. Forward: 0 -> 2 -> 3 -> 1 -> 0.
constexpr int8_t kStep[4][4] = {
    //  to 00  01  10  11
    {0, -1, +1, X},  // from 00
    {+1, 0, X, -1},  // from 01
    {-1, X, 0, +1},  // from 10
    {X, +1, -1, 0},  // from 11
};

}  // namespace

int8_t quadrature_step(uint8_t from_ab, uint8_t to_ab) { return kStep[from_ab & 3u][to_ab & 3u]; }

void QuadratureDecoder::reset(bool a, bool b, uint64_t window_ns) {
  *this = QuadratureDecoder{};
  state_ = next_ = static_cast<uint8_t>((a ? 2u : 0u) | (b ? 1u : 0u));
  window_ns_ = window_ns;
}

void QuadratureDecoder::commit() {
  if (!pending_) return;
  pending_ = false;
  const int8_t step = kStep[state_][next_];
  if (step == kIllegalStep) {
    ++counters_.illegal;
  } else {
    count_ += step;
  }
  state_ = next_;
}

void QuadratureDecoder::settle(uint64_t now_ns) {
  if (pending_ && now_ns - pending_since_ >= window_ns_) commit();
}

void QuadratureDecoder::on_edge(int line, bool level, uint64_t ts) {
  // An edge after the window closed starts a new sample; within it, joins the pending one.
  if (pending_ && ts - pending_since_ > window_ns_) commit();
  const uint8_t bit = line == 0 ? 2u : 1u;
  const bool was = (next_ & bit) != 0;
  if (was == level) {
    ++counters_.missed_edges;  // the opposite edge never reached us
    return;
  }
  ++counters_.edges;
  next_ = static_cast<uint8_t>(level ? (next_ | bit) : (next_ & ~bit));
  if (!pending_) {
    pending_ = true;
    pending_since_ = ts;
  }
}

void QuadratureDecoder::on_index(uint64_t, int64_t home_count, bool every_pulse) {
  commit();
  ++counters_.index_pulses;
  if (homed_ && !every_pulse) return;
  if (homed_ && count_ != home_count) ++counters_.index_corrections;
  count_ = home_count;
  homed_ = true;
}

void QuadratureDecoder::resync(bool a, bool b) {
  commit();
  const uint8_t observed = static_cast<uint8_t>((a ? 2u : 0u) | (b ? 1u : 0u));
  if (observed == state_) return;
  ++counters_.resyncs;
  state_ = next_ = observed;
}

int32_t counts_to_angle(int64_t count, uint32_t counts_per_turn, int32_t offset) {
  const int64_t cpt = counts_per_turn;
  int64_t r = count % cpt;
  if (r < 0) r += cpt;
  // round half up of r * 2^32 / cpt: floor((2 r 2^32 + cpt) / (2 cpt)); r < 2^30 keeps it in 64 bits.
  const uint64_t num = (static_cast<uint64_t>(r) << 33) + static_cast<uint64_t>(cpt);
  const uint64_t turns = num / (2u * static_cast<uint64_t>(cpt));                       // 0 .. 2^32
  const uint32_t angle = static_cast<uint32_t>(turns) + static_cast<uint32_t>(offset);  // wraps mod 2^32
  return static_cast<int32_t>(angle);
}

}  // namespace sinew::hal::gpio
