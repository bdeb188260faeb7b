// libFuzzer target: any bytes after the first as a frame log file, read back
// with FrameLogReader (header, record scan, payload decode) from an
// in-memory file. When the first byte is odd the harness first rewrites the
// header's and every complete record's checksum, so mutations reach the
// record and payload parsers instead of stopping at a checksum. The reader
// must return a prefix of intact records and account for every byte.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "hal/output/checksum.hpp"
#include "hal/output/frame_log_format.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "hal/output/le_bytes.hpp"

namespace {

using namespace sinew::hal::output;

void fix_checksums(uint8_t* p, size_t size) {
  if (size < kLogHeaderBytes) return;
  store_u64(p + 32, xxh64({p, 32}));
  size_t at = kLogHeaderBytes;
  while (size - at >= kRecordHeaderBytes) {
    const uint32_t length = load_u32(p + at + 4);
    if (length > size - at - kRecordHeaderBytes) return;  // a torn tail stays torn
    store_u64(p + at + 8, record_checksum(p + at + 4, {p + at + kRecordHeaderBytes, length}));
    at += kRecordHeaderBytes + length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  // One anonymous in-memory file for every input: nothing touches a disk.
  static const int fd = memfd_create("frame-log-fuzz", MFD_CLOEXEC);
  static const std::string path = "/proc/self/fd/" + std::to_string(fd);
  if (fd < 0) __builtin_trap();
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1) fix_checksums(reinterpret_cast<uint8_t*>(bytes.data()), bytes.size());
  if (ftruncate(fd, 0) != 0 || pwrite(fd, bytes.data(), bytes.size(), 0) != static_cast<ssize_t>(bytes.size()))
    __builtin_trap();
  FrameLogReader reader;
  std::string error;
  if (!reader.open(path, &error)) {
    if (error.empty()) __builtin_trap();
    return 0;
  }
  DecodedPose pose;
  uint64_t records = 0;
  while (reader.next(&pose)) {
    ++records;
    const FrameShape& shape = reader.shape();
    if (pose.vertex_count != shape.vertex_count || pose.input_count != shape.input_count) __builtin_trap();
    for (const auto& axis : pose.position)
      if (axis.size() != pose.vertex_count) __builtin_trap();
    if (pose.input_value.size() != pose.input_count || pose.input_status.size() != pose.input_count) __builtin_trap();
  }
  if (reader.records_read() != records || reader.stop() == LogStop::kNone) __builtin_trap();
  if (reader.stop_offset() < kLogHeaderBytes || reader.stop_offset() + reader.discarded_bytes() != bytes.size())
    __builtin_trap();
  if (reader.clean_end() && reader.discarded_bytes() != 0) __builtin_trap();
  if (reader.stop_message().empty()) __builtin_trap();
  return 0;
}
