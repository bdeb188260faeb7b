// libFuzzer target: any bytes as a sequence of received UDP stream datagrams
// (each a 2-byte little-endian length, then its bytes), fed in order to the
// receiver's reassembler; every frame it completes is decoded as a pose
// payload, as sinew-receive does. The first byte sets the reassembler's
// options (stream filter, slots, frame size limit) and, when odd, has the
// harness rewrite each datagram's length field and checksum so mutations
// reach the fragment layout and reassembly instead of stopping there.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hal/output/checksum.hpp"
#include "hal/output/le_bytes.hpp"
#include "hal/output/pose_decode.hpp"
#include "hal/output/udp_datagram.hpp"
#include "host_tools/receiver/reassembler.hpp"

namespace {

using namespace sinew::hal::output;

void fix_datagram(std::vector<uint8_t>* d) {
  if (d->size() < kUdpHeaderBytes) return;
  uint8_t* p = d->data();
  store_u16(p + 10, static_cast<uint16_t>(d->size() - kUdpHeaderBytes));
  store_u64(p + 32, xxh64_concat({p, 32}, {p + kUdpHeaderBytes, d->size() - kUdpHeaderBytes}));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t mode = data[0];
  sinew::receiver::ReassemblerOptions options;
  options.slots = 1 + ((mode >> 1) & 3);
  // A frame completes only when all its bytes arrived, and an input holds at
  // most max_len (16 KiB) of them: a 64 KiB limit keeps every frame an input
  // can complete, while the receiver's 64 MiB default had each input that
  // declares a huge frame zero-fill that much (page faults, not parsing).
  // Larger declarations still reach the refusal path.
  options.max_frame_bytes = (mode & 0x08) ? 4096 : 65536;
  if (mode & 0x10) options.stream_id = 0x01020304;
  sinew::receiver::Reassembler reassembler(options);
  DecodedPose pose;
  std::string why;
  uint64_t fed = 0, delivered = 0;
  size_t i = 1;
  while (size - i >= 2) {
    const size_t length = std::min<size_t>(load_u16(data + i), size - i - 2);
    std::vector<uint8_t> datagram(data + i + 2, data + i + 2 + length);
    i += 2 + length;
    if (mode & 1) fix_datagram(&datagram);
    ++fed;
    if (!reassembler.feed(datagram)) continue;
    ++delivered;
    const std::span<const uint8_t> frame = reassembler.frame_payload();
    if (frame.size() > options.max_frame_bytes) __builtin_trap();
    if (options.stream_id != 0 && reassembler.stream_id() != options.stream_id) __builtin_trap();
    if (decode_pose(frame, &pose, &why)) {
      for (const auto& axis : pose.position)
        if (axis.size() != pose.vertex_count) __builtin_trap();
    } else if (why.empty()) {
      __builtin_trap();
    }
  }
  const sinew::receiver::ReceiverStats& s = reassembler.stats();
  if (s.datagrams != fed || s.frames_delivered != delivered) __builtin_trap();
  return 0;
}
