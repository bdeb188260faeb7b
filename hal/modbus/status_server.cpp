#include "status_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

namespace sinew::hal::modbus {

namespace {

constexpr int kPollIntervalMs = 50;            // how soon the thread notices stop()
constexpr uint32_t kClientTimeoutUs = 100000;  // a request must arrive whole within this

std::string why(const char* what) { return std::string("status server: ") + what + ": " + std::strerror(errno); }

}  // namespace

std::unique_ptr<StatusServer> StatusServer::create(const StatusServerConfig& config, std::string* error) {
  in_addr addr{};
  if (inet_pton(AF_INET, config.bind_address.c_str(), &addr) != 1)
    return *error = "status server: bind address '" + config.bind_address + "' is not an IPv4 address", nullptr;
  if (config.input_count > kMaxStatusInputs) return *error = "status server: too many inputs", nullptr;
  if (config.max_clients < 1) return *error = "status server: max_clients must be positive", nullptr;
  std::unique_ptr<StatusServer> server(new StatusServer(config));
  if (!server->open(error)) return nullptr;
  server->thread_ = std::thread([s = server.get()] { s->run(); });
  return server;
}

StatusServer::StatusServer(const StatusServerConfig& config)
    : config_(config), exchange_(std::vector<uint16_t>(status_register_count(config.input_count), 0)) {}

bool StatusServer::open(std::string* error) {
  ctx_ = modbus_new_tcp(config_.bind_address.c_str(), config_.port);
  if (ctx_ == nullptr) return *error = why("context"), false;
  // Bounded waits for slow or half-sent requests, so one client cannot hold
  // the thread (and libmodbus's flush-after-error sleeps stay short).
  modbus_set_indication_timeout(ctx_, 0, kClientTimeoutUs);
  modbus_set_byte_timeout(ctx_, 0, kClientTimeoutUs);
  modbus_set_response_timeout(ctx_, 0, kClientTimeoutUs);
  listen_fd_ = modbus_tcp_listen(ctx_, config_.max_clients);
  if (listen_fd_ < 0) return *error = why("listen"), false;
  // Non-blocking: a connection reset between poll() and accept() must not block.
  fcntl(listen_fd_, F_SETFL, fcntl(listen_fd_, F_GETFL) | O_NONBLOCK);
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  if (getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &length) != 0)
    return *error = why("getsockname"), false;
  port_ = ntohs(bound.sin_port);
  const auto registers = static_cast<unsigned>(status_register_count(config_.input_count));
  mapping_ = modbus_mapping_new_start_address(0, 0, 0, 0, 0, registers, 0, registers);
  if (mapping_ == nullptr) return *error = why("register mapping"), false;
  return true;
}

StatusServer::~StatusServer() {
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
  for (int fd : clients_) ::close(fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
  if (mapping_ != nullptr) modbus_mapping_free(mapping_);
  if (ctx_ != nullptr) modbus_free(ctx_);  // its socket is one of ours, already closed
}

void StatusServer::publish(const StatusUpdate& update) {
  std::vector<uint16_t>& image = exchange_.back();
  encode_status(update, ++heartbeat_, image);
  exchange_.publish();
}

void StatusServer::run() {
  std::vector<pollfd> fds;
  fds.reserve(static_cast<size_t>(config_.max_clients) + 1);
  while (!stopping_.load()) {
    fds.clear();
    fds.push_back(pollfd{listen_fd_, POLLIN, 0});
    for (int fd : clients_) fds.push_back(pollfd{fd, POLLIN, 0});
    if (poll(fds.data(), fds.size(), kPollIntervalMs) <= 0) continue;
    for (size_t i = 1; i < fds.size(); ++i) {
      if (fds[i].revents == 0) continue;
      if (!serve_request(fds[i].fd)) {
        ::close(fds[i].fd);
        clients_.erase(std::find(clients_.begin(), clients_.end(), fds[i].fd));
      }
    }
    if ((fds[0].revents & POLLIN) != 0) accept_client();
  }
}

void StatusServer::accept_client() {
  const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
  if (fd < 0) return;
  if (clients_.size() >= static_cast<size_t>(config_.max_clients)) {
    ::close(fd);
    return;
  }
  clients_.push_back(fd);
}

bool StatusServer::serve_request(int fd) {
  std::array<uint8_t, MODBUS_TCP_MAX_ADU_LENGTH> request{};
  modbus_set_socket(ctx_, fd);
  const int length = modbus_receive(ctx_, request.data());
  if (length < 0) return false;  // closed, reset, garbled or half-sent: drop the client
  if (length > 0) answer(request.data(), length);
  return true;
}

void StatusServer::answer(const uint8_t* request, int length) {
  const int header = modbus_get_header_length(ctx_);
  if (length < header + 5) return;
  const uint8_t function = request[header];
  if (function != MODBUS_FC_READ_HOLDING_REGISTERS && function != MODBUS_FC_READ_INPUT_REGISTERS) {
    // Read-only: writes (and everything else) are refused, never applied.
    refused_.fetch_add(1, std::memory_order_relaxed);
    modbus_reply_exception(ctx_, request, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
    return;
  }
  const int count = (request[header + 3] << 8) | request[header + 4];
  if (count < 1 || count > MODBUS_MAX_READ_REGISTERS) {
    refused_.fetch_add(1, std::memory_order_relaxed);
    modbus_reply_exception(ctx_, request, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
    return;
  }
  refresh_mapping();
  // Reads past the image are answered "illegal data address" by libmodbus.
  if (modbus_reply(ctx_, request, length, mapping_) > 0) reads_served_.fetch_add(1, std::memory_order_relaxed);
}

void StatusServer::refresh_mapping() {
  if (!exchange_.refresh()) return;
  const std::vector<uint16_t>& image = exchange_.front();
  std::copy(image.begin(), image.end(), mapping_->tab_registers);
  std::copy(image.begin(), image.end(), mapping_->tab_input_registers);
}

}  // namespace sinew::hal::modbus
