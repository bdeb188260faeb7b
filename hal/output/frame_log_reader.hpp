// Reads a frame log back (host side; allocates). Returns every intact record
// in order and stops at the first record that is torn or damaged, reporting
// how many bytes were left unread and why. It never skips a damaged record:
// what it returns is always a prefix of what was written.
#pragma once

#include <cstdint>
#include <string>

#include "frame_compression.hpp"
#include "frame_log_scan.hpp"
#include "frame_shape.hpp"
#include "pose_decode.hpp"

namespace sinew::hal::output {

class FrameLogReader {
 public:
  FrameLogReader() = default;
  ~FrameLogReader() { close(); }
  FrameLogReader(const FrameLogReader&) = delete;
  FrameLogReader& operator=(const FrameLogReader&) = delete;

  // Opens the log and checks its header (magic, version, checksum).
  bool open(const std::string& path, std::string* error);
  void close();

  const FrameShape& shape() const { return shape_; }
  // The log's metadata block (a recording's run description); empty for a
  // version-1 log.
  const std::string& metadata() const { return metadata_; }
  // Whether the records are compressed (frame_compression.hpp).
  bool compressed() const { return compressed_; }

  // The next intact record, decoded; false at the end or at a damaged record.
  bool next(DecodedPose* out);

  // Once next() has returned false:
  LogStop stop() const { return scan_.stop(); }
  bool clean_end() const { return scan_.stop() == LogStop::kEnd; }
  uint64_t records_read() const { return scan_.records(); }
  uint64_t stop_offset() const { return scan_.offset(); }               // where reading stopped
  uint64_t discarded_bytes() const { return scan_.discarded_bytes(); }  // bytes after it
  std::string stop_message() const;  // e.g. "torn-tail at offset 1234: record cut short (...); 56 bytes discarded"

 private:
  int fd_ = -1;
  FrameShape shape_;
  std::string metadata_;
  bool compressed_ = false;
  FrameDecompressor decompressor_;
  RecordScanner scan_;
};

}  // namespace sinew::hal::output
