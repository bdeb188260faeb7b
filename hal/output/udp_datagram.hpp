// UDP stream datagram: a 40-byte header then one fragment of a pose payload
// (layout in docs/frame-formats.md). A frame that fits one datagram is sent
// as a single fragment; a larger one is split at fixed offsets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sinew::hal::output {

inline constexpr uint8_t kUdpMagic[4] = {'S', 'N', 'W', 'U'};
inline constexpr uint8_t kUdpVersion = 1;
inline constexpr size_t kUdpHeaderBytes = 40;
inline constexpr size_t kUdpDefaultMaxDatagram = 1400;  // fits a 1500-byte MTU with IP/UDP headers to spare

struct UdpFragment {
  uint32_t stream_id = 0;  // random per sender run: a restart is visible to the receiver
  uint64_t sequence = 0;   // frame number within the stream, +1 per frame offered (sent or dropped)
  uint16_t fragment_index = 0;
  uint16_t fragment_count = 0;
  uint32_t total_bytes = 0;     // the whole frame's payload
  uint32_t payload_offset = 0;  // where this fragment's bytes go in the frame's payload
  uint16_t payload_bytes = 0;   // this fragment's bytes (the datagram's length minus the header)
};

// Writes the header for `f` and `payload` (whose size is f.payload_bytes) into `out`.
void write_udp_header(const UdpFragment& f, std::span<const uint8_t> payload, uint8_t out[kUdpHeaderBytes]);

enum class DatagramCheck : uint8_t { kOk, kTooShort, kBadMagic, kBadVersion, kBadLength, kBadLayout, kBadChecksum };
const char* datagram_check_name(DatagramCheck c);

// Parses and verifies one received datagram; on kOk fills *f and *payload
// (a view into `datagram`).
DatagramCheck parse_udp_datagram(std::span<const uint8_t> datagram, UdpFragment* f, std::span<const uint8_t>* payload);

}  // namespace sinew::hal::output
