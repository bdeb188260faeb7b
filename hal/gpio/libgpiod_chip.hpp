// GpioChip over libgpiod 1.6 (the v1 character-device ABI, Debian 12):
// inputs requested with both-edge events, one event fd per line made
// non-blocking, read with gpiod_line_event_read_fd_multiple and merged by
// kernel timestamp (CLOCK_MONOTONIC since Linux 5.7). A v2 backend
// (libgpiod 2.x, one request for all lines, sequence numbers that reveal
// overflow) would be a second implementation of the same interface.
#pragma once

#include <memory>
#include <string>

#include "line_io.hpp"

namespace sinew::hal::gpio {

// device: a chip name ("gpiochip0"), a path ("/dev/gpiochip0"), a number
// ("0") or a label, as gpiod_chip_open_lookup accepts. consumer: the label
// the kernel shows for the requested lines. Null with a message on failure.
std::unique_ptr<GpioChip> open_libgpiod_chip(const std::string& device, const std::string& consumer,
                                             std::string* error);

}  // namespace sinew::hal::gpio
