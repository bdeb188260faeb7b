// Append-only frame log: one self-checking record per tick (format in
// docs/frame-formats.md). A process crash loses at most the record being
// written; a power cut loses what the fsync policy has not yet synced.
//
// Fsync policy: each write() is one pwrite() into the page cache (durable
// against a process crash as soon as it returns). fdatasync() runs every
// `sync_every_frames` records (0: only in flush() and close()); it blocks the
// calling thread for the storage's write latency, so a real-time tick keeps
// it at 0 and calls flush() from a non-real-time thread, or accepts the stall.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "frame_compression.hpp"
#include "frame_shape.hpp"
#include "hal/common/output_sink.hpp"
#include "hal/common/pose_frame.hpp"

namespace sinew::hal::output {

struct FrameLogOptions {
  uint32_t sync_every_frames = 0;  // fdatasync after this many records; 0 = only on flush()/close()
  // Text written once after the header (a version-2 log); empty: none (a
  // version-1 log). An existing log is appended to only if its metadata is
  // the same. At most kMaxLogMetadataBytes.
  std::string metadata;
  // Compressed records (frame_compression.hpp; docs/frame-formats.md): zstd
  // at `compression_level` (1..19) on the delta to the previous record, a
  // key record every `key_every_frames`. An existing log is appended to only
  // if it is compressed the same way (compressed or not).
  bool compress = false;
  int compression_level = 1;
  uint32_t key_every_frames = 1000;
};

struct FrameLogStats {
  uint64_t frames_written = 0;
  uint64_t frames_dropped = 0;        // write failed (e.g. disk full); the partial record was cut off
  uint64_t frames_rejected = 0;       // frame does not match the log's shape
  uint64_t record_bytes_written = 0;  // records as written (compressed, when they are)
  uint64_t payload_bytes = 0;         // the same records' pose payloads before compression
  uint64_t syncs = 0;
  uint64_t sync_errors = 0;
  int last_errno = 0;
  bool appended = false;        // opened an existing log
  uint64_t tail_bytes_cut = 0;  // torn tail removed from an existing log at open
};

class FrameLogWriter final : public OutputSink {
 public:
  FrameLogWriter() = default;
  ~FrameLogWriter() override { close(); }
  FrameLogWriter(const FrameLogWriter&) = delete;
  FrameLogWriter& operator=(const FrameLogWriter&) = delete;

  // Creates the log (atomically: header written to a temporary file, synced,
  // renamed), or opens an existing one to append. An existing log must have
  // the same shape; a torn last record (at most one record long) is cut off;
  // larger damage is refused, so appending never buries intact records behind
  // a corrupt one. Takes an exclusive lock: one writer per file. Never
  // follows a symbolic link at the path or at the temporary file's name, and
  // refuses a world-writable directory without the sticky bit, an existing
  // file that is not a regular file, has other names (hard links) or, in a
  // world-writable directory, belongs to another user (safe_create.hpp).
  bool open(const std::string& path, const FrameShape& shape, const FrameLogOptions& options, std::string* error);

  // Appends one record. False if the frame was rejected or dropped (counted).
  // No allocation; one pwrite(), plus fdatasync() when the policy says so;
  // compressing first when the options say so.
  bool write(const PoseFrame& frame) override;

  void flush() override;  // fdatasync now
  void close() override;  // syncs what is unsynced, then closes

  bool is_open() const { return fd_ >= 0; }
  uint64_t file_bytes() const { return end_; }
  const FrameLogStats& stats() const { return stats_; }
  // The name in reports ("frame-log" unless set: the daemon gives the sink's).
  const char* name() const override { return name_.c_str(); }
  void set_name(std::string name) { name_ = std::move(name); }
  std::string status_line() const override;  // allocates: for periodic reports only

 private:
  bool open_existing(const std::string& path, std::string* error);
  void sync();

  int fd_ = -1;
  FrameShape shape_;
  FrameLogOptions options_;
  std::vector<uint8_t> record_;  // one record: header + largest payload
  FrameCompressor compressor_;
  uint64_t end_ = 0;  // end of the last complete record
  uint32_t unsynced_ = 0;
  FrameLogStats stats_;
  std::string name_ = "frame-log";
};

}  // namespace sinew::hal::output
