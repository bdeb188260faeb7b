#include "frame_log_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "frame_log_format.hpp"
#include "pose_codec.hpp"

namespace sinew::hal::output {

bool FrameLogReader::open(const std::string& path, std::string* error) {
  close();
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) return *error = "cannot open " + path + ": " + std::strerror(errno), false;
  struct stat st {};
  LogPreamble preamble;
  std::string why = "cannot stat";
  if (::fstat(fd_, &st) != 0 || !read_log_preamble(fd_, static_cast<uint64_t>(st.st_size), &preamble, &why)) {
    *error = path + ": " + why;
    close();
    return false;
  }
  shape_ = preamble.shape;
  metadata_ = std::move(preamble.metadata);
  compressed_ = preamble.compressed;
  const uint64_t file_bytes = static_cast<uint64_t>(st.st_size);
  const uint64_t record_bytes = file_bytes > preamble.records_offset ? file_bytes - preamble.records_offset : 0;
  if (compressed_ && !decompressor_.init(static_cast<size_t>(max_pose_payload_bytes(shape_)), record_bytes, &why)) {
    *error = path + ": " + why;
    close();
    return false;
  }
  scan_.start(fd_, static_cast<uint64_t>(st.st_size), shape_, preamble.records_offset, compressed_);
  return true;
}

void FrameLogReader::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool FrameLogReader::next(DecodedPose* out) {
  std::span<const uint8_t> payload;
  if (fd_ < 0 || !scan_.next(&payload)) return false;
  std::string why;
  if (compressed_ && !decompressor_.decode(payload, &payload, &why)) {
    scan_.reject_last(LogStop::kBadPayload, why);
    return false;
  }
  if (!decode_pose(payload, out, &why)) {
    scan_.reject_last(LogStop::kBadPayload, why);
    return false;
  }
  FrameShape got;
  got.vertex_count = out->vertex_count;
  got.input_count = out->input_count;
  got.length_exponent = out->length_exponent;
  got.normals = shape_.normals;
  if (got != shape_ || (out->has_normals && !shape_.normals)) {
    scan_.reject_last(LogStop::kBadPayload, "record does not match the log header's shape");
    return false;
  }
  return true;
}

std::string FrameLogReader::stop_message() const {
  return std::string(log_stop_name(scan_.stop())) + " " + scan_.stop_detail() + "; " +
         std::to_string(scan_.discarded_bytes()) + " bytes discarded";
}

}  // namespace sinew::hal::output
