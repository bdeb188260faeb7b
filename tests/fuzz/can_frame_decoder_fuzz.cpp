// libFuzzer target: any bytes as a sequence of received CAN frames (id, flags,
// length, payload, time step) through both decoders: the default joint
// stream (classic and CAN FD layouts) and DBC-style signals. Decoding must
// never crash, and every accepted sample must be within its configured range.
#include <cstddef>
#include <cstdint>
#include <string>

#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/signal_decoder.hpp"

namespace {

using namespace sinew::hal::can;

struct Decoders {
  JointStreamDecoder classic, fd;
  SignalDecoder signals;
  Decoders() {
    std::string error;
    JointStreamConfig c = default_joint_stream_config(16, false, 10'000'000);
    for (auto& f : c.frames)
      for (auto& j : f.joints) j.min = -(1 << 29), j.max = 1 << 29;
    if (!classic.configure(c, &error)) __builtin_trap();
    if (!fd.configure(default_joint_stream_config(16, true, 10'000'000), &error)) __builtin_trap();
    SignalSpec a;
    a.can_id = 0x300, a.start_bit = 7, a.length = 16, a.byte_order = ByteOrder::kMotorola, a.is_signed = true;
    a.scale = 0.01, a.min = -90, a.max = 90, a.input = 0;
    SignalSpec b;
    b.can_id = 0x18FF0001, b.extended = true, b.start_bit = 3, b.length = 61, a.is_signed = false;
    b.scale = 1e-17, b.min = 0, b.max = 20, b.input = 1;
    if (!signals.configure({a, b}, &error)) __builtin_trap();
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Decoders d;
  FrameDecode out;
  uint64_t t = 0;
  size_t i = 0;
  while (i + 6 <= size) {
    CanFrame f;
    const uint8_t selector = data[i];
    f.id = (selector & 0x80)   ? 0x100u + (data[i + 1] & 0x1F)
           : (selector & 0x40) ? 0x180u + (data[i + 1] & 3)
                               : uint32_t{data[i + 1]} << 3 | 0x300u;
    if (selector & 0x20) f.id = 0x18FF0001, f.extended = true;
    f.fd = (selector & 0x10) != 0;
    f.kind = (selector & 0x0C) == 0x0C ? FrameKind::kRemote : FrameKind::kData;
    f.len = static_cast<uint8_t>(data[i + 2] % (f.fd ? kFdMaxLen + 1 : kClassicMaxLen + 1));
    t += data[i + 3] * 100'000u;
    f.timestamp_ns = t;
    i += 4;
    for (uint8_t k = 0; k < f.len && i < size; ++k) f.data[k] = data[i++];
    for (FrameDecoder* decoder : {static_cast<FrameDecoder*>(&d.classic), static_cast<FrameDecoder*>(&d.fd),
                                  static_cast<FrameDecoder*>(&d.signals)}) {
      decoder->decode(f, out);
      if (out.sample_count > kMaxSamplesPerFrame || out.rejection_count > kMaxSamplesPerFrame) __builtin_trap();
      if (decoder == &d.classic)
        for (const auto& s : out.accepted())
          if (s.value < -(1 << 29) || s.value > (1 << 29)) __builtin_trap();
    }
  }
  return 0;
}
