#include "web_server.hpp"

#include <civetweb.h>

#include <algorithm>

namespace sinew::view {

bool WebServer::start(const std::string& web_root, uint16_t port, std::string greeting, std::string* error) {
  greeting_ = std::move(greeting);
  // Local only: the viewer shows a rig's live state, it is not a public service.
  const std::string ports = "127.0.0.1:" + std::to_string(port);
  const char* options[] = {"document_root", web_root.c_str(), "listening_ports", ports.c_str(), "num_threads", "4",
                           nullptr};
  mg_init_library(0);
  if (mg_check_feature(16) == 0) return *error = "civetweb was built without WebSocket support", false;
  mg_callbacks callbacks{};
  context_ = mg_start(&callbacks, this, options);
  if (context_ == nullptr) return *error = "cannot serve on " + ports + " (port in use?)", false;
  mg_set_websocket_handler(context_, "/stream", on_connect, on_ready, on_data, on_close, this);
  return true;
}

void WebServer::stop() {
  if (context_ == nullptr) return;
  mg_stop(context_);
  context_ = nullptr;
  mg_exit_library();
}

int WebServer::on_connect(const mg_connection*, void*) { return 0; }  // 0: accept

void WebServer::on_ready(mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_TEXT, s->greeting_.data(), s->greeting_.size());
  const std::lock_guard<std::mutex> lock(s->mutex_);
  s->pages_.push_back(conn);
  s->new_pages_ = true;
}

int WebServer::on_data(mg_connection*, int bits, char* data, size_t length, void* self) {
  auto* s = static_cast<WebServer*>(self);
  const int opcode = bits & 0x0f;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (opcode == MG_WEBSOCKET_OPCODE_TEXT && length > 0 && length < 256) {
    const std::lock_guard<std::mutex> lock(s->mutex_);
    s->commands_.emplace_back(data, length);
  }
  return 1;  // keep the connection
}

void WebServer::on_close(const mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  const std::lock_guard<std::mutex> lock(s->mutex_);
  s->pages_.erase(std::remove(s->pages_.begin(), s->pages_.end(), conn), s->pages_.end());
}

void WebServer::broadcast(const std::vector<uint8_t>& message) {
  const std::lock_guard<std::mutex> lock(mutex_);
  for (mg_connection* conn : pages_)
    mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_BINARY, reinterpret_cast<const char*>(message.data()), message.size());
}

bool WebServer::take_new_pages() {
  const std::lock_guard<std::mutex> lock(mutex_);
  const bool any = new_pages_;
  new_pages_ = false;
  return any;
}

std::vector<std::string> WebServer::take_commands() {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  out.swap(commands_);
  return out;
}

size_t WebServer::pages() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pages_.size();
}

}  // namespace sinew::view
