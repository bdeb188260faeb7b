// [[source]] entries for the buses: "can" (SocketCAN), "candump" (replay of a
// candump log), "simulated-rig" (the rig simulator on the in-process CAN bus,
// optionally with its Modbus device on loopback) and "modbus" (libmodbus TCP
// or RTU). Keys are listed in firmware/config/default.toml.
#pragma once

#include <memory>
#include <string>

#include "config.hpp"
#include "hal/common/input_source.hpp"
#include "loaded_rig.hpp"

namespace sinew::firmware {

// Null with a message naming the source and key on a bad entry.
std::unique_ptr<hal::InputSource> make_bus_source(const SourceConfig& source, const LoadedRig& rig,
                                                  const DaemonConfig& config, uint64_t start_ns, std::string* error);

}  // namespace sinew::firmware
