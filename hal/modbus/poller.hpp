// The Modbus client thread: connects, runs one poll cycle (every planned read
// request) per period, converts the readings, and publishes a snapshot to the
// tick through a TripleBuffer. All blocking I/O (connect, request, response
// timeout, back-off waits) happens here, never on the tick.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "backoff.hpp"
#include "hal/common/triple_buffer.hpp"
#include "poll_snapshot.hpp"
#include "poller_config.hpp"
#include "poller_stats.hpp"
#include "read_outcome.hpp"
#include "request_plan.hpp"

namespace sinew::hal::modbus {

class ModbusLink;

class Poller {
 public:
  // `config` must have passed validate().
  explicit Poller(PollerConfig config);
  ~Poller();
  Poller(const Poller&) = delete;
  Poller& operator=(const Poller&) = delete;

  // Creates the libmodbus context and starts the thread; false with a message
  // if libmodbus refused the link parameters. Connecting happens on the thread.
  bool start(std::string* error);
  // Stops and joins the thread; returns within about one response timeout.
  void stop();

  // The consumer side belongs to the tick (one consumer thread).
  TripleBuffer<PollSnapshot>& exchange() { return exchange_; }
  const TripleBuffer<PollSnapshot>& exchange() const { return exchange_; }
  const PollerStats& stats() const { return stats_; }
  const PollerConfig& config() const { return config_; }
  std::span<const ReadRequest> plan() const { return plan_; }

 private:
  struct CycleResult {
    size_t with_data = 0;    // requests answered with registers
    size_t answered = 0;     // ... or with an exception
    bool link_lost = false;  // the link must be reopened before the next cycle
  };

  void run();
  CycleResult poll_cycle();
  void accept_registers(const ReadRequest& request, std::span<const uint16_t> regs, uint64_t now_ns);
  void record_failure(const ReadRequest& request, const ReadResult& result);
  void mark_unanswered(size_t first_request);
  void publish();
  bool sleep_for(uint64_t ns);  // false once stopping

  PollerConfig config_;
  std::vector<ReadRequest> plan_;
  std::unique_ptr<ModbusLink> link_;
  PollSnapshot work_;  // the poller's copy, published after every cycle
  TripleBuffer<PollSnapshot> exchange_;
  PollerStats stats_;
  Backoff backoff_;

  std::thread thread_;
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  std::atomic<bool> stopping_{false};
};

}  // namespace sinew::hal::modbus
