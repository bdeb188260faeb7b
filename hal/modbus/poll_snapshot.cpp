#include "poll_snapshot.hpp"

namespace sinew::hal::modbus {

const char* channel_status_name(ChannelStatus s) {
  switch (s) {
    case ChannelStatus::kNeverRead:
      return "never read";
    case ChannelStatus::kOk:
      return "ok";
    case ChannelStatus::kOutOfRange:
      return "out of range";
    case ChannelStatus::kException:
      return "exception";
    case ChannelStatus::kNoResponse:
      return "no response";
  }
  return "unknown";
}

}  // namespace sinew::hal::modbus
