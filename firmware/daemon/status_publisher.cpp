#include "status_publisher.hpp"

namespace sinew::firmware {

std::unique_ptr<StatusPublisher> StatusPublisher::create(const DaemonConfig& config, const Runtime& runtime,
                                                         std::string* error) {
  if (config.status.modbus_port < 0) return nullptr;
  hal::modbus::StatusServerConfig server;
  server.bind_address = config.status.modbus_bind;
  server.port = static_cast<uint16_t>(config.status.modbus_port);
  server.input_count = runtime.health().values().size();
  server.max_clients = config.status.modbus_max_clients;
  std::string why;
  auto created = hal::modbus::StatusServer::create(server, &why);
  if (!created) {
    *error = "[status] modbus_port " + std::to_string(config.status.modbus_port) + ": " + why;
    return nullptr;
  }
  std::unique_ptr<StatusPublisher> p(new StatusPublisher());
  p->server_ = std::move(created);
  p->source_states_.assign(runtime.sources().size(), hal::SourceState{});
  return p;
}

void StatusPublisher::publish(const Runtime& runtime, const hal::PoseFrame& frame, uint64_t step_ns) {
  const auto sources = runtime.sources();
  for (size_t i = 0; i < sources.size() && i < source_states_.size(); ++i) source_states_[i] = sources[i]->state();
  hal::modbus::StatusUpdate update;
  update.tick = frame.tick;
  update.last_step_ns = step_ns;
  update.stale_count = static_cast<uint32_t>(runtime.health().stale_count());
  update.input_status = {frame.input_status, frame.input_status != nullptr ? frame.input_count : 0u};
  update.source_states = source_states_;
  server_->publish(update);
}

std::string StatusPublisher::status_line() const {
  return "status registers: Modbus TCP port " + std::to_string(server_->port()) + ", " +
         std::to_string(server_->reads_served()) + " reads served, " + std::to_string(server_->requests_refused()) +
         " requests refused";
}

}  // namespace sinew::firmware
