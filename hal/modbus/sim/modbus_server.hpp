// The simulated rig's Modbus side: a real libmodbus TCP server on 127.0.0.1,
// on its own thread. Serves the holding and input registers it is given,
// answers an exception for a chosen request address, or goes mute (accepts
// and reads requests but never answers: a response timeout at the client). Every wait is bounded; stop() (or the
// destructor) ends it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

struct _modbus;
struct _modbus_mapping_t;

namespace sinew::hal::sim {

class ModbusServer {
 public:
  static constexpr int kRegisters = 256;  // holding and input registers 0..255

  ModbusServer();
  ~ModbusServer();
  ModbusServer(const ModbusServer&) = delete;
  ModbusServer& operator=(const ModbusServer&) = delete;

  // Called on the server thread with the monotonic time whenever a client's
  // request is about to be read, before the server decides to answer, fail
  // or stay mute: a device that measures on demand sets its registers and
  // its faults there (ModbusFeeder), so what a request reads is the value at
  // that request's time, however the threads are scheduled. Set before start().
  void set_sampler(std::function<void(uint64_t now_ns)> sampler) { sampler_ = std::move(sampler); }

  // Listens on 127.0.0.1:port (0: any free port). False if it cannot bind.
  bool start(uint16_t port = 0);
  // Closes the listener and every connection (clients see the link drop).
  void stop();
  uint16_t port() const { return port_; }

  void set_holding(uint16_t address, uint16_t value);
  void set_input(uint16_t address, uint16_t value);
  // Two registers holding `value`, in the given word order.
  void set_holding32(uint16_t address, uint32_t value, bool high_word_first);
  void set_input32(uint16_t address, uint32_t value, bool high_word_first);
  // Any read request starting at `address` gets exception `code`; address -1 turns it off.
  void fail_reads_at(int address, uint8_t code);
  void set_mute(bool mute) { mute_.store(mute); }

  uint64_t requests() const { return requests_.load(); }
  uint64_t connections() const { return connections_.load(); }
  // Mute mode: per connection the client hung up, the time from its last
  // request to the hang-up (how long the client waited for an answer).
  std::vector<uint64_t> silences_ns() const;

 private:
  void run();
  void serve(int fd, size_t client);
  void listen_for_mute(int fd, size_t client);
  void drop(size_t client);

  _modbus* ctx_ = nullptr;
  _modbus_mapping_t* mapping_ = nullptr;
  int listen_fd_ = -1;
  uint16_t port_ = 0;
  struct Client {
    int fd = -1;
    uint64_t last_request_ns = 0;
  };
  std::vector<Client> clients_;  // server thread only
  std::function<void(uint64_t)> sampler_;

  mutable std::mutex mutex_;  // mapping values, failure injection, silences
  int fail_address_ = -1;
  uint8_t fail_code_ = 0;
  std::vector<uint64_t> silences_;

  std::atomic<bool> mute_{false};
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> requests_{0};
  std::atomic<uint64_t> connections_{0};
  std::thread thread_;
};

uint64_t now_ns();  // CLOCK_MONOTONIC

}  // namespace sinew::hal::sim
