// Walks the records of a frame log file, one intact record at a time, and
// says where and why it stopped. Shared by the reader and by the writer,
// which scans an existing log before appending to it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "frame_log_format.hpp"
#include "frame_shape.hpp"

namespace sinew::hal::output {

enum class LogStop : uint8_t {
  kNone,             // still reading
  kEnd,              // clean end: the file ends exactly after a record
  kTornTail,         // the file ends inside a record (crash or power cut while writing it)
  kBadRecordHeader,  // record magic or length is wrong
  kBadChecksum,      // record complete but its checksum does not match
  kBadPayload,       // checksum matches but the payload does not decode to the log's shape
  kIoError,          // read error
};

const char* log_stop_name(LogStop s);

class RecordScanner {
 public:
  // Scans `fd` (not owned; read with pread) of `file_size` bytes from the
  // first record after the file header. Allocates a buffer for the largest record.
  // records_offset: where the first record starts (after the preamble);
  // compressed: the log's records are compressed (their lengths vary).
  void start(int fd, uint64_t file_size, const FrameShape& shape, uint64_t records_offset = kLogHeaderBytes,
             bool compressed = false);

  // The next intact record's payload (valid until the next call); false once stopped.
  bool next(std::span<const uint8_t>* payload);

  // Marks the record just returned as unusable (the caller could not decode it).
  void reject_last(LogStop why, std::string detail);

  uint64_t offset() const { return offset_; }  // end of the last intact record
  uint64_t records() const { return records_; }
  LogStop stop() const { return stop_; }
  const std::string& stop_detail() const { return detail_; }
  uint64_t discarded_bytes() const { return file_size_ - offset_; }
  // Bytes held for one record: the largest the shape allows, but never more
  // than the file could hold.
  size_t buffer_bytes() const { return buffer_.size(); }

 private:
  bool halt(LogStop why, std::string detail);

  int fd_ = -1;
  uint64_t file_size_ = 0;
  uint64_t offset_ = 0;
  uint64_t last_offset_ = 0;
  uint64_t records_ = 0;
  FrameShape shape_;
  bool compressed_ = false;
  std::vector<uint8_t> buffer_;
  LogStop stop_ = LogStop::kNone;
  std::string detail_;
};

}  // namespace sinew::hal::output
