// The bus-fed [[source]] types: "can" (SocketCAN), "candump" (replay of a
// candump log), "simulated-rig" (the rig simulator on the in-process CAN
// bus, optionally with its Modbus device on loopback), "modbus" (libmodbus
// TCP or RTU) and "gpio" (libgpiod encoders and limit switches). Their keys
// and registry entries are in sources.cpp; default.toml documents them.
#pragma once

#include <memory>
#include <string>

#include "hal/common/input_source.hpp"
#include "sources.hpp"

namespace sinew::firmware {

// Each opens its source from a [[source]] table; null with a message naming
// the source and key on a bad entry.
std::unique_ptr<hal::InputSource> open_can_source(const SourceConfig& s, const SourceSetup& setup, std::string* error);
std::unique_ptr<hal::InputSource> open_candump_source(const SourceConfig& s, const SourceSetup& setup,
                                                      std::string* error);
std::unique_ptr<hal::InputSource> open_simulated_rig_source(const SourceConfig& s, const SourceSetup& setup,
                                                            std::string* error);
std::unique_ptr<hal::InputSource> open_modbus_source(const SourceConfig& s, const SourceSetup& setup,
                                                     std::string* error);
std::unique_ptr<hal::InputSource> open_gpio_source(const SourceConfig& s, const SourceSetup& setup, std::string* error);

}  // namespace sinew::firmware
