#include "frame_log_scan.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "frame_log_format.hpp"
#include "le_bytes.hpp"

namespace sinew::hal::output {

const char* log_stop_name(LogStop s) {
  switch (s) {
    case LogStop::kNone:
      return "none";
    case LogStop::kEnd:
      return "end";
    case LogStop::kTornTail:
      return "torn-tail";
    case LogStop::kBadRecordHeader:
      return "bad-record-header";
    case LogStop::kBadChecksum:
      return "bad-checksum";
    case LogStop::kBadPayload:
      return "bad-payload";
    case LogStop::kIoError:
      return "io-error";
  }
  return "unknown";
}

namespace {

// Reads exactly n bytes at `offset`; false on error (errno set) or early end.
bool pread_all(int fd, uint8_t* dst, size_t n, uint64_t offset) {
  while (n > 0) {
    const ssize_t got = ::pread(fd, dst, n, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      if (got == 0) errno = EIO;
      return false;
    }
    dst += got;
    n -= static_cast<size_t>(got);
    offset += static_cast<uint64_t>(got);
  }
  return true;
}

}  // namespace

void RecordScanner::start(int fd, uint64_t file_size, const FrameShape& shape, uint64_t records_offset,
                          bool compressed) {
  fd_ = fd;
  file_size_ = file_size;
  offset_ = last_offset_ = records_offset;
  records_ = 0;
  shape_ = shape;
  compressed_ = compressed;
  // A record is read only when the file holds all of it, so the buffer never
  // needs more than the file's bytes after its header: sizing it from the
  // header's counts alone let a 41-byte file claim a gigabyte.
  const uint64_t after_header = file_size > records_offset ? file_size - records_offset : 0;
  buffer_.assign(static_cast<size_t>(std::min(max_record_bytes(shape, compressed),
                                              std::max<uint64_t>(after_header, kRecordHeaderBytes))),
                 0);
  stop_ = LogStop::kNone;
  detail_.clear();
}

bool RecordScanner::halt(LogStop why, std::string detail) {
  stop_ = why;
  detail_ = "at offset " + std::to_string(offset_) + ": " + detail;
  return false;
}

bool RecordScanner::next(std::span<const uint8_t>* payload) {
  if (stop_ != LogStop::kNone) return false;
  const uint64_t left = file_size_ - offset_;
  if (left == 0) return halt(LogStop::kEnd, "end of file");
  if (left < kRecordHeaderBytes)
    return halt(LogStop::kTornTail, "record header cut short (" + std::to_string(left) + " of " +
                                        std::to_string(kRecordHeaderBytes) + " bytes)");
  uint8_t* head = buffer_.data();
  if (!pread_all(fd_, head, kRecordHeaderBytes, offset_)) return halt(LogStop::kIoError, std::strerror(errno));
  if (load_u32(head) != kRecordMagic) return halt(LogStop::kBadRecordHeader, "bad record magic");
  const uint32_t length = load_u32(head + 4);
  if (!record_length_allowed(shape_, length, compressed_))
    return halt(LogStop::kBadRecordHeader, "record length " + std::to_string(length) + " does not fit the log's shape");
  if (left < kRecordHeaderBytes + length)
    return halt(LogStop::kTornTail, "record cut short (" + std::to_string(left) + " of " +
                                        std::to_string(kRecordHeaderBytes + length) + " bytes)");
  uint8_t* body = head + kRecordHeaderBytes;
  if (!pread_all(fd_, body, length, offset_ + kRecordHeaderBytes)) return halt(LogStop::kIoError, std::strerror(errno));
  if (load_u64(head + 8) != record_checksum(head + 4, {body, length}))
    return halt(LogStop::kBadChecksum, "record checksum mismatch");
  *payload = {body, length};
  last_offset_ = offset_;
  offset_ += kRecordHeaderBytes + length;
  ++records_;
  return true;
}

void RecordScanner::reject_last(LogStop why, std::string detail) {
  offset_ = last_offset_;
  --records_;
  halt(why, std::move(detail));
}

}  // namespace sinew::hal::output
