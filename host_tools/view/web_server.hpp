// The viewer's HTTP and WebSocket server (civetweb): serves the page's files
// from one directory and pushes messages to every page connected to /stream.
// Pages send short text commands back (play, pause, speed X, seek T).
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

struct mg_context;
struct mg_connection;

namespace sinew::view {

class WebServer {
 public:
  WebServer() = default;
  ~WebServer() { stop(); }
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Listens on 127.0.0.1:port, serving files under web_root. greeting: the
  // text message each page receives first when it connects (the rig).
  bool start(const std::string& web_root, uint16_t port, std::string greeting, std::string* error);
  void stop();

  // Sends one binary message to every connected page.
  void broadcast(const std::vector<uint8_t>& message);
  // Pages connected since the last call (they need the latest frame now).
  bool take_new_pages();
  // Commands received since the last call, in order.
  std::vector<std::string> take_commands();
  size_t pages() const;

 private:
  static int on_connect(const mg_connection* conn, void* self);
  static void on_ready(mg_connection* conn, void* self);
  static int on_data(mg_connection* conn, int bits, char* data, size_t length, void* self);
  static void on_close(const mg_connection* conn, void* self);

  mg_context* context_ = nullptr;
  std::string greeting_;
  mutable std::mutex mutex_;
  std::vector<mg_connection*> pages_;
  std::vector<std::string> commands_;
  bool new_pages_ = false;
};

}  // namespace sinew::view
