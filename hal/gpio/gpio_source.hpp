// The tick's view of GPIO inputs: an InputSource whose latch() drains the
// pending edge events without blocking (kernel timestamps), applies those up
// to the tick's time to the quadrature decoders and limit-switch debouncers,
// and emits one angle sample per encoder. Also the external sync input
// (wait_sync: a tick starts on its active edge) and the status/fault output.
// Nothing allocates after create().
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "debounce.hpp"
#include "gpio_source_config.hpp"
#include "hal/common/input_source.hpp"
#include "line_io.hpp"
#include "quadrature.hpp"

namespace sinew::hal::gpio {

// Status bits a GPIO sample carries beside hal::SampleStatus (bits 0..3 are
// the shared ones): the input's limit switch is pressed (debounced).
enum GpioSampleStatus : uint8_t {
  kSampleAtMinLimit = 1u << 4,
  kSampleAtMaxLimit = 1u << 5,
};

struct SyncEdge {
  WaitResult result = WaitResult::kTimeout;
  uint64_t timestamp_ns = 0;  // kernel time of the active edge (kReady)
  uint32_t missed = 0;        // further active edges found pending: ticks the master started without us
};

struct GpioCounters {
  uint64_t events = 0;  // edge events applied
  uint64_t read_errors = 0;
  uint64_t sync_edges = 0;
  uint64_t sync_missed = 0;
  uint64_t sync_timeouts = 0;
  uint64_t late_events = 0;      // events older than one already applied (applied as if simultaneous)
  uint64_t overflow_checks = 0;  // latches that re-read the levels after a full kernel FIFO
};

class GpioSource : public InputSource {
 public:
  // Opens config.chip with libgpiod, validates, requests the lines.
  static std::unique_ptr<GpioSource> create(GpioSourceConfig config, std::string* error);
  // The same on any backend (the simulated twin).
  static std::unique_ptr<GpioSource> create(GpioSourceConfig config, std::unique_ptr<GpioChip> chip,
                                            std::string* error);
  ~GpioSource() override;

  const char* name() const override { return config_.name.c_str(); }
  // Applies the events with timestamp <= until_ns (later ones wait for the
  // next latch) and emits, per encoder, its angle as of until_ns with the
  // limit-switch bits of its input. An encoder with an index line emits
  // nothing until its first index pulse (not homed).
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, hal::InputHealth& health) override;
  // ok; degraded when the last latch saw illegal transitions or lost edges;
  // down after a read error.
  hal::SourceState state() const override { return state_; }
  std::string status_line() const override;
  // The sync trigger (`[loop] trigger = "sync"`): with a sync line, its
  // active edge is an arrival, read without waiting, reported from its
  // timestamp on until a latch at or after it. Counted as wait_sync counts.
  uint8_t arrival_signals() const override { return sync_ ? hal::kSignalsSync : hal::kSignalsNothing; }
  hal::Arrival arrival(uint64_t now_ns) override;

  // Lockstep with a master: waits up to timeout_ns (0 polls) for the sync
  // line's active edge. Events that are not active edges are consumed.
  SyncEdge wait_sync(uint64_t timeout_ns);
  // Drives the fault output: asserted (active level) when `fault`. It is
  // asserted from create() until the first set_fault(false), and again on
  // destruction. False if no fault line is configured or the write failed.
  bool set_fault(bool fault);

  const GpioSourceConfig& config() const { return config_; }
  const GpioCounters& counters() const { return counters_; }
  const QuadratureDecoder& encoder(size_t i) const { return encoders_[i]; }
  bool limit_pressed(size_t i) const { return limits_[i].stable(); }
  const Debouncer& limit(size_t i) const { return limits_[i]; }
  // kSampleAtMinLimit / kSampleAtMaxLimit bits of a rig input.
  uint8_t limit_flags(uint16_t input) const;

 private:
  GpioSource(GpioSourceConfig config, std::unique_ptr<GpioChip> chip);
  bool init(std::string* error);
  void apply(const LineEvent& event);
  void resync_levels(uint64_t now_ns);

  enum class Role : uint8_t { kNone, kA, kB, kIndex, kLimit };
  struct LineRole {
    Role role = Role::kNone;
    bool active_low = false;
    uint32_t index = 0;  // encoder or limit index
  };

  GpioSourceConfig config_;
  std::unique_ptr<GpioChip> chip_;
  std::unique_ptr<LineGroup> inputs_;
  std::unique_ptr<LineGroup> sync_;
  std::unique_ptr<OutputLine> fault_;
  std::vector<LineRole> roles_;  // by line offset
  std::vector<QuadratureDecoder> encoders_;
  std::vector<Debouncer> limits_;
  std::vector<LineEvent> pending_;  // staged events [head_, tail_)
  size_t head_ = 0;
  size_t tail_ = 0;
  std::vector<LineEvent> sync_buffer_;
  std::vector<uint8_t> levels_;  // read-back levels, request order
  uint64_t seen_overflows_ = 0;
  uint64_t last_ts_ = 0;
  uint64_t last_problems_ = 0;  // illegal + missed edges at the previous latch
  bool sync_pending_ = false;   // an active sync edge read by arrival(), not yet latched
  uint64_t sync_pending_ns_ = 0;
  hal::SourceState state_ = hal::SourceState::kOk;
  GpioCounters counters_;
};

}  // namespace sinew::hal::gpio
