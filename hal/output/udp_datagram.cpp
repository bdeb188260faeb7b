#include "udp_datagram.hpp"

#include <cstring>

#include "checksum.hpp"
#include "le_bytes.hpp"

namespace sinew::hal::output {

namespace {
constexpr size_t kChecksumAt = 32;  // the checksum covers bytes [0, 32) then the payload
}

void write_udp_header(const UdpFragment& f, std::span<const uint8_t> payload, uint8_t out[kUdpHeaderBytes]) {
  std::memcpy(out, kUdpMagic, sizeof(kUdpMagic));
  out[4] = kUdpVersion;
  out[5] = static_cast<uint8_t>(kUdpHeaderBytes);
  store_u16(out + 6, f.fragment_index);
  store_u16(out + 8, f.fragment_count);
  store_u16(out + 10, f.payload_bytes);
  store_u32(out + 12, f.stream_id);
  store_u64(out + 16, f.sequence);
  store_u32(out + 24, f.total_bytes);
  store_u32(out + 28, f.payload_offset);
  store_u64(out + kChecksumAt, xxh64_concat({out, kChecksumAt}, payload));
}

const char* datagram_check_name(DatagramCheck c) {
  switch (c) {
    case DatagramCheck::kOk:
      return "ok";
    case DatagramCheck::kTooShort:
      return "too-short";
    case DatagramCheck::kBadMagic:
      return "bad-magic";
    case DatagramCheck::kBadVersion:
      return "bad-version";
    case DatagramCheck::kBadLength:
      return "bad-length";
    case DatagramCheck::kBadLayout:
      return "bad-layout";
    case DatagramCheck::kBadChecksum:
      return "bad-checksum";
  }
  return "unknown";
}

DatagramCheck parse_udp_datagram(std::span<const uint8_t> datagram, UdpFragment* f, std::span<const uint8_t>* payload) {
  if (datagram.size() < kUdpHeaderBytes) return DatagramCheck::kTooShort;
  const uint8_t* p = datagram.data();
  if (std::memcmp(p, kUdpMagic, sizeof(kUdpMagic)) != 0) return DatagramCheck::kBadMagic;
  if (p[4] != kUdpVersion || p[5] != kUdpHeaderBytes) return DatagramCheck::kBadVersion;
  UdpFragment h;
  h.fragment_index = load_u16(p + 6);
  h.fragment_count = load_u16(p + 8);
  h.payload_bytes = load_u16(p + 10);
  h.stream_id = load_u32(p + 12);
  h.sequence = load_u64(p + 16);
  h.total_bytes = load_u32(p + 24);
  h.payload_offset = load_u32(p + 28);
  if (datagram.size() != kUdpHeaderBytes + h.payload_bytes) return DatagramCheck::kBadLength;
  const std::span<const uint8_t> body = datagram.subspan(kUdpHeaderBytes);
  if (load_u64(p + kChecksumAt) != xxh64_concat({p, kChecksumAt}, body)) return DatagramCheck::kBadChecksum;
  if (h.fragment_count == 0 || h.fragment_index >= h.fragment_count || h.payload_bytes == 0 ||
      uint64_t{h.payload_offset} + h.payload_bytes > h.total_bytes)
    return DatagramCheck::kBadLayout;
  *f = h;
  *payload = body;
  return DatagramCheck::kOk;
}

}  // namespace sinew::hal::output
