// A read-only Modbus TCP server for a PLC or HMI: serves the runtime's health
// (tick count, step time, stale inputs, source states, per-input status) as
// holding and input registers (status_registers.hpp). Its own thread runs
// modbus_receive / modbus_reply; the tick publishes through a TripleBuffer,
// so it never waits for a client. Every function other than "read holding
// registers" and "read input registers" is answered with exception 01
// (illegal function): nothing can be written.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hal/common/triple_buffer.hpp"
#include "status_registers.hpp"

struct _modbus;
struct _modbus_mapping_t;

namespace sinew::hal::modbus {

struct StatusServerConfig {
  std::string bind_address = "127.0.0.1";  // IPv4 address; "0.0.0.0" = every interface
  uint16_t port = 1502;                    // 0 = any free port (see port())
  size_t input_count = 0;                  // rig inputs to expose (registers 32..)
  int max_clients = 4;                     // further connections are closed at once
};

class StatusServer {
 public:
  // Binds and starts serving; null with a message on error (e.g. port in use).
  static std::unique_ptr<StatusServer> create(const StatusServerConfig& config, std::string* error);
  ~StatusServer();
  StatusServer(const StatusServer&) = delete;
  StatusServer& operator=(const StatusServer&) = delete;

  uint16_t port() const { return port_; }

  // Tick thread (one publisher): encodes the image and hands it over.
  // Wait-free, allocation-free.
  void publish(const StatusUpdate& update);

  // Any thread.
  uint64_t reads_served() const { return reads_served_.load(std::memory_order_relaxed); }
  uint64_t requests_refused() const { return refused_.load(std::memory_order_relaxed); }

 private:
  explicit StatusServer(const StatusServerConfig& config);
  bool open(std::string* error);
  void run();
  void accept_client();
  bool serve_request(int fd);  // false: drop the client
  void answer(const uint8_t* request, int length);
  void refresh_mapping();

  StatusServerConfig config_;
  _modbus* ctx_ = nullptr;
  _modbus_mapping_t* mapping_ = nullptr;
  int listen_fd_ = -1;
  uint16_t port_ = 0;
  std::vector<int> clients_;

  TripleBuffer<std::vector<uint16_t>> exchange_;
  uint16_t heartbeat_ = 0;  // publisher only

  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> reads_served_{0};
  std::atomic<uint64_t> refused_{0};
};

}  // namespace sinew::hal::modbus
