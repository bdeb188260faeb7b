#include "frame_log_writer.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "frame_log_format.hpp"
#include "frame_log_scan.hpp"
#include "hal/common/safe_create.hpp"
#include "pose_codec.hpp"

namespace sinew::hal::output {

namespace {

std::string os_error(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

bool pwrite_all(int fd, const uint8_t* src, size_t n, uint64_t offset) {
  while (n > 0) {
    const ssize_t put = ::pwrite(fd, src, n, static_cast<off_t>(offset));
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) {
      if (put == 0) errno = EIO;
      return false;
    }
    src += put;
    n -= static_cast<size_t>(put);
    offset += static_cast<uint64_t>(put);
  }
  return true;
}

// A new log appears complete or not at all: the header goes into a fresh
// temporary file, is synced, and the file is renamed into place. Returns the
// temporary file's descriptor, which is the log's once renamed.
int create_log(OutputDir& dir, const FrameShape& shape, const FrameLogOptions& options, std::string* error) {
  const int fd = dir.create_temp(0644, error);
  if (fd < 0) return -1;
  const std::vector<uint8_t> preamble = encode_log_preamble(shape, options.metadata, options.compress);
  if (!pwrite_all(fd, preamble.data(), preamble.size(), 0) || ::fdatasync(fd) != 0) {
    *error = dir.subject() + ": cannot write its header: " + std::strerror(errno);
    ::close(fd);
    dir.discard();
    return -1;
  }
  if (!dir.commit(error)) return ::close(fd), -1;
  return fd;
}

}  // namespace

bool FrameLogWriter::open(const std::string& path, const FrameShape& shape, const FrameLogOptions& options,
                          std::string* error) {
  close();
  stats_ = {};
  shape_ = shape;
  options_ = options;
  if (max_pose_payload_bytes(shape) == 0) return *error = "frame too large for a frame log", false;
  if (options.metadata.size() > kMaxLogMetadataBytes)
    return *error = "frame log metadata larger than " + std::to_string(kMaxLogMetadataBytes) + " bytes", false;
  if (options.compress && !compressor_.init(static_cast<size_t>(max_pose_payload_bytes(shape)),
                                            options.compression_level, options.key_every_frames, error))
    return *error = "frame log " + path + ": " + *error, false;

  // Never through a symbolic link, in a directory others cannot swap the file in (safe_create.hpp).
  OutputDir dir;
  if (!dir.open(path, "frame log", error)) return false;
  bool missing = false;
  fd_ = dir.open_existing(O_RDWR, &missing, error);
  if (missing) {
    fd_ = create_log(dir, shape, options, error);
  } else if (fd_ >= 0) {
    stats_.appended = true;
  }
  if (fd_ < 0) return false;
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    *error = errno == EWOULDBLOCK ? path + " is open in another writer" : os_error("cannot lock", path);
    return close(), false;
  }
  if (!open_existing(path, error)) return close(), false;
  record_.assign(static_cast<size_t>(max_record_bytes(shape)), 0);
  return true;
}

bool FrameLogWriter::open_existing(const std::string& path, std::string* error) {
  struct stat st {};
  if (::fstat(fd_, &st) != 0) return *error = os_error("cannot stat", path), false;
  const auto size = static_cast<uint64_t>(st.st_size);
  if (size == 0) {  // an empty file (e.g. made by the caller): give it a header
    const std::vector<uint8_t> preamble = encode_log_preamble(shape_, options_.metadata, options_.compress);
    if (!pwrite_all(fd_, preamble.data(), preamble.size(), 0) || ::fdatasync(fd_) != 0)
      return *error = os_error("cannot write", path), false;
    end_ = preamble.size();
    return true;
  }
  LogPreamble in_log;
  std::string why;
  if (!read_log_preamble(fd_, size, &in_log, &why)) return *error = path + ": " + why, false;
  if (in_log.shape != shape_)
    return *error = path + ": incompatible frame log (" + describe_shape_mismatch(in_log.shape, shape_) + ")", false;
  if (in_log.compressed != options_.compress)
    return *error = path + ": incompatible frame log (its records are " +
                    (in_log.compressed ? "compressed, the sink's are not" : "not compressed, the sink's are") + ")",
           false;
  // A recording appended to must describe the same run (rig, rate, layers).
  if (in_log.metadata != options_.metadata)
    return *error = path + ": incompatible frame log (its metadata describes another run" +
                    (in_log.metadata.empty() || options_.metadata.empty() ? ", or none" : "") + ")",
           false;

  RecordScanner scan;
  scan.start(fd_, size, shape_, in_log.records_offset, in_log.compressed);
  std::span<const uint8_t> payload;
  while (scan.next(&payload)) {
  }
  if (scan.stop() == LogStop::kIoError) return *error = path + ": read error " + scan.stop_detail(), false;
  if (scan.discarded_bytes() > max_record_bytes(shape_, in_log.compressed))
    return *error = path + ": damaged " + scan.stop_detail() + "; appending would cut " +
                    std::to_string(scan.discarded_bytes()) + " bytes, more than one record: refusing",
           false;
  if (scan.discarded_bytes() > 0) {
    if (::ftruncate(fd_, static_cast<off_t>(scan.offset())) != 0 || ::fdatasync(fd_) != 0)
      return *error = os_error("cannot cut the torn tail of", path), false;
    stats_.tail_bytes_cut = scan.discarded_bytes();
  }
  end_ = scan.offset();
  return true;
}

static_assert(FrameCompressor::head_room >= kRecordHeaderBytes, "the record header goes before the packed payload");

bool FrameLogWriter::write(const PoseFrame& frame) {
  if (fd_ < 0) return ++stats_.frames_dropped, false;
  const std::span<uint8_t> body(record_.data() + kRecordHeaderBytes, record_.size() - kRecordHeaderBytes);
  const size_t n = encode_pose(frame, shape_, body);
  if (n == 0) return ++stats_.frames_rejected, false;
  uint8_t* record = record_.data();
  std::span<const uint8_t> stored = body.first(n);
  if (options_.compress) {
    // The compressor leaves room for the record header before its output.
    const std::span<uint8_t> packed = compressor_.encode(stored);
    if (packed.empty()) return ++stats_.frames_dropped, false;
    record = packed.data() - kRecordHeaderBytes;
    stored = packed;
  }
  encode_record_header(stored, record);
  const size_t total = kRecordHeaderBytes + stored.size();
  if (!pwrite_all(fd_, record, total, end_)) {
    stats_.last_errno = errno;
    ++stats_.frames_dropped;
    compressor_.restart();  // the next record may not be a delta to one that is not in the file
    // Cut any partial record, so the next one follows an intact log.
    if (::ftruncate(fd_, static_cast<off_t>(end_)) != 0) stats_.last_errno = errno;
    return false;
  }
  end_ += total;
  ++stats_.frames_written;
  stats_.record_bytes_written += total;
  stats_.payload_bytes += n;
  ++unsynced_;
  if (options_.sync_every_frames != 0 && unsynced_ >= options_.sync_every_frames) sync();
  return true;
}

void FrameLogWriter::sync() {
  unsynced_ = 0;
  ++stats_.syncs;
  if (::fdatasync(fd_) != 0) {
    ++stats_.sync_errors;
    stats_.last_errno = errno;
  }
}

void FrameLogWriter::flush() {
  if (fd_ >= 0) sync();
}

void FrameLogWriter::close() {
  if (fd_ < 0) return;
  if (unsynced_ > 0) sync();
  ::close(fd_);  // also releases the lock
  fd_ = -1;
}

std::string FrameLogWriter::status_line() const {
  std::string s = std::string(name()) + ": " + std::to_string(stats_.frames_written) + " written, " +
                  std::to_string(stats_.frames_dropped) + " dropped, " + std::to_string(stats_.frames_rejected) +
                  " rejected, " + std::to_string(end_) + " bytes, " + std::to_string(stats_.syncs) + " syncs";
  if (options_.compress && stats_.record_bytes_written > 0)
    s += ", zstd " + std::to_string(stats_.payload_bytes / stats_.record_bytes_written) + "x";
  if (stats_.sync_errors > 0) s += ", " + std::to_string(stats_.sync_errors) + " sync errors";
  if (stats_.last_errno != 0) s += ", last error: " + std::string(std::strerror(stats_.last_errno));
  return s;
}

}  // namespace sinew::hal::output
