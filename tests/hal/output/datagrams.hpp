// Builds the datagrams of one frame the way the sender does, for feeding the
// reassembler directly.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "hal/output/udp_datagram.hpp"

namespace sinew::test {

using Datagram = std::vector<uint8_t>;

inline std::vector<Datagram> fragment_frame(const std::vector<uint8_t>& payload, uint32_t stream, uint64_t sequence,
                                            size_t fragment_bytes) {
  const size_t count = (payload.size() + fragment_bytes - 1) / fragment_bytes;
  std::vector<Datagram> out;
  for (size_t i = 0; i < count; ++i) {
    const size_t offset = i * fragment_bytes;
    const size_t n = std::min(fragment_bytes, payload.size() - offset);
    hal::output::UdpFragment f;
    f.stream_id = stream;
    f.sequence = sequence;
    f.fragment_index = static_cast<uint16_t>(i);
    f.fragment_count = static_cast<uint16_t>(count);
    f.total_bytes = static_cast<uint32_t>(payload.size());
    f.payload_offset = static_cast<uint32_t>(offset);
    f.payload_bytes = static_cast<uint16_t>(n);
    Datagram d(hal::output::kUdpHeaderBytes + n);
    std::copy_n(payload.begin() + static_cast<std::ptrdiff_t>(offset), n, d.begin() + hal::output::kUdpHeaderBytes);
    hal::output::write_udp_header(f, {d.data() + hal::output::kUdpHeaderBytes, n}, d.data());
    out.push_back(std::move(d));
  }
  return out;
}

// A payload whose bytes depend on the sequence number.
inline std::vector<uint8_t> payload_for(uint64_t sequence, size_t bytes) {
  std::vector<uint8_t> p(bytes);
  for (size_t i = 0; i < bytes; ++i) p[i] = static_cast<uint8_t>((i * 131 + sequence * 17 + (i >> 8)) & 0xFF);
  return p;
}

}  // namespace sinew::test
