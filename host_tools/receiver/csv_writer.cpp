#include "csv_writer.hpp"

#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstring>
#include <vector>

#include "hal/common/safe_create.hpp"
#include "hal/output/checksum.hpp"
#include "hal/output/le_bytes.hpp"

namespace sinew::receiver {

namespace {

uint64_t positions_digest(const hal::output::DecodedPose& pose) {
  std::vector<uint8_t> bytes(size_t{pose.vertex_count} * 12);
  for (size_t c = 0; c < 3; ++c)
    hal::output::store_i32_array(bytes.data() + c * 4 * pose.vertex_count, pose.position[c].data(), pose.vertex_count);
  return hal::output::xxh64(bytes);
}

}  // namespace

bool CsvWriter::open(const std::string& path, bool vertices, std::string* error) {
  close();
  // A new file renamed into place: never written through a link planted at the path (safe_create.hpp).
  const int fd = hal::create_replacing(path, "CSV file", 0666, error);
  if (fd < 0) return false;
  file_ = ::fdopen(fd, "w");
  if (file_ == nullptr) {
    *error = "CSV file " + path + ": " + std::strerror(errno);
    return ::close(fd), false;
  }
  vertices_ = vertices;
  have_header_ = false;
  rows_ = skipped_ = 0;
  return true;
}

bool CsvWriter::write(uint64_t sequence, const hal::output::DecodedPose& pose) {
  if (file_ == nullptr) return false;
  if (!have_header_) {
    vertex_count_ = pose.vertex_count;
    input_count_ = pose.input_count;
    std::fputs("sequence,tick,timestamp_ns,length_exponent,vertex_count,input_count,positions_xxh64", file_);
    for (uint32_t i = 0; i < input_count_; ++i) std::fprintf(file_, ",value_%" PRIu32 ",status_%" PRIu32, i, i);
    if (vertices_)
      for (uint32_t v = 0; v < vertex_count_; ++v)
        std::fprintf(file_, ",x_%" PRIu32 ",y_%" PRIu32 ",z_%" PRIu32, v, v, v);
    std::fputc('\n', file_);
    have_header_ = true;
  }
  if (pose.vertex_count != vertex_count_ || pose.input_count != input_count_) return ++skipped_, false;
  std::fprintf(file_, "%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRId32 ",%" PRIu32 ",%" PRIu32 ",%016" PRIx64, sequence,
               pose.tick, pose.timestamp_ns, pose.length_exponent, pose.vertex_count, pose.input_count,
               positions_digest(pose));
  for (uint32_t i = 0; i < input_count_; ++i)
    std::fprintf(file_, ",%" PRId32 ",%u", pose.input_value[i], static_cast<unsigned>(pose.input_status[i]));
  if (vertices_)
    for (uint32_t v = 0; v < vertex_count_; ++v)
      std::fprintf(file_, ",%" PRId32 ",%" PRId32 ",%" PRId32, pose.position[0][v], pose.position[1][v],
                   pose.position[2][v]);
  std::fputc('\n', file_);
  ++rows_;
  return true;
}

bool CsvWriter::close() {
  if (file_ == nullptr) return true;
  const bool ok = std::ferror(file_) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  return ok && closed;
}

}  // namespace sinew::receiver
