#include "hal/modbus/sim/modbus_server.hpp"

#include <modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <ctime>

namespace sinew::hal::sim {

namespace {

constexpr int kPollMs = 5;
constexpr size_t kMaxClients = 16;

}  // namespace

uint64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

ModbusServer::ModbusServer() {
  mapping_ = modbus_mapping_new(0, 0, kRegisters, kRegisters);
  // Reserved up front so the server thread does not allocate while a test
  // counts allocations.
  clients_.reserve(kMaxClients);
  silences_.reserve(256);
}

ModbusServer::~ModbusServer() {
  stop();
  modbus_mapping_free(mapping_);
}

bool ModbusServer::start(uint16_t port) {
  if (thread_.joinable()) return true;
  ctx_ = modbus_new_tcp("127.0.0.1", port);
  if (ctx_ == nullptr) return false;
  modbus_set_indication_timeout(ctx_, 0, 200000);
  modbus_set_byte_timeout(ctx_, 0, 200000);
  listen_fd_ = modbus_tcp_listen(ctx_, static_cast<int>(kMaxClients));
  if (listen_fd_ < 0) {
    modbus_free(ctx_);
    ctx_ = nullptr;
    return false;
  }
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &length);
  port_ = ntohs(bound.sin_port);
  stopping_.store(false);
  thread_ = std::thread([this] { run(); });
  return true;
}

void ModbusServer::stop() {
  if (!thread_.joinable()) return;
  stopping_.store(true);
  thread_.join();
  while (!clients_.empty()) drop(clients_.size() - 1);
  ::close(listen_fd_);
  listen_fd_ = -1;
  modbus_free(ctx_);
  ctx_ = nullptr;
}

void ModbusServer::set_holding(uint16_t address, uint16_t value) {
  std::lock_guard<std::mutex> lock(mutex_);
  mapping_->tab_registers[address] = value;
}

void ModbusServer::set_input(uint16_t address, uint16_t value) {
  std::lock_guard<std::mutex> lock(mutex_);
  mapping_->tab_input_registers[address] = value;
}

void ModbusServer::set_holding32(uint16_t address, uint32_t value, bool high_word_first) {
  const auto high = static_cast<uint16_t>(value >> 16);
  const auto low = static_cast<uint16_t>(value & 0xFFFFu);
  std::lock_guard<std::mutex> lock(mutex_);
  mapping_->tab_registers[address] = high_word_first ? high : low;
  mapping_->tab_registers[address + 1] = high_word_first ? low : high;
}

void ModbusServer::set_input32(uint16_t address, uint32_t value, bool high_word_first) {
  const auto high = static_cast<uint16_t>(value >> 16);
  const auto low = static_cast<uint16_t>(value & 0xFFFFu);
  std::lock_guard<std::mutex> lock(mutex_);
  mapping_->tab_input_registers[address] = high_word_first ? high : low;
  mapping_->tab_input_registers[address + 1] = high_word_first ? low : high;
}

void ModbusServer::fail_reads_at(int address, uint8_t code) {
  std::lock_guard<std::mutex> lock(mutex_);
  fail_address_ = address;
  fail_code_ = code;
}

std::vector<uint64_t> ModbusServer::silences_ns() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return silences_;
}

void ModbusServer::run() {
  std::array<pollfd, kMaxClients + 1> fds{};
  while (!stopping_.load()) {
    fds[0] = pollfd{listen_fd_, POLLIN, 0};
    for (size_t i = 0; i < clients_.size(); ++i) fds[i + 1] = pollfd{clients_[i].fd, POLLIN, 0};
    const size_t polled = clients_.size() + 1;
    if (poll(fds.data(), polled, kPollMs) <= 0) continue;
    // Back to front, so dropping a client keeps the earlier indices valid.
    for (size_t i = polled - 1; i >= 1; --i) {
      if (fds[i].revents == 0) continue;
      if (sampler_) sampler_(now_ns());
      if (mute_.load()) {
        listen_for_mute(fds[i].fd, i - 1);
      } else {
        serve(fds[i].fd, i - 1);
      }
    }
    if ((fds[0].revents & POLLIN) != 0) {
      const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (fd >= 0 && clients_.size() < kMaxClients) {
        clients_.push_back(Client{fd, 0});
        connections_.fetch_add(1);
      } else if (fd >= 0) {
        ::close(fd);
      }
    }
  }
}

void ModbusServer::serve(int fd, size_t client) {
  std::array<uint8_t, MODBUS_TCP_MAX_ADU_LENGTH> request{};
  modbus_set_socket(ctx_, fd);
  const int length = modbus_receive(ctx_, request.data());
  if (length < 0) return drop(client);
  if (length == 0) return;
  requests_.fetch_add(1);
  const int header = modbus_get_header_length(ctx_);
  const int address = (request[static_cast<size_t>(header) + 1] << 8) | request[static_cast<size_t>(header) + 2];
  std::lock_guard<std::mutex> lock(mutex_);
  if (address == fail_address_) {
    modbus_reply_exception(ctx_, request.data(), fail_code_);
  } else {
    modbus_reply(ctx_, request.data(), length, mapping_);
  }
}

void ModbusServer::listen_for_mute(int fd, size_t client) {
  std::array<uint8_t, 512> bytes{};
  const ssize_t n = recv(fd, bytes.data(), bytes.size(), MSG_DONTWAIT);
  if (n > 0) {
    requests_.fetch_add(1);
    clients_[client].last_request_ns = now_ns();
    return;
  }
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;
  if (clients_[client].last_request_ns != 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    silences_.push_back(now_ns() - clients_[client].last_request_ns);
  }
  drop(client);
}

void ModbusServer::drop(size_t client) {
  ::close(clients_[client].fd);
  clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(client));
}

}  // namespace sinew::hal::sim
