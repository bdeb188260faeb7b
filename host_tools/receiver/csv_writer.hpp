// Writes received frames as CSV rows: one row per frame, the header from the
// first frame's counts. Columns: sequence, tick, timestamp_ns,
// length_exponent, vertex_count, input_count, positions_xxh64 (of the
// little-endian x, y, z arrays), value_<i> and status_<i> per input, then,
// with vertices enabled, x_<v>, y_<v>, z_<v> per vertex (raw Q12.20).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "hal/output/pose_decode.hpp"

namespace sinew::receiver {

class CsvWriter {
 public:
  CsvWriter() = default;
  ~CsvWriter() { close(); }
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  // Creates the file anew, empty, replacing a regular file at the path; a
  // symbolic link there is refused, never followed (safe_create.hpp).
  bool open(const std::string& path, bool vertices, std::string* error);
  // Appends one row; frames whose counts differ from the first one are skipped (counted).
  bool write(uint64_t sequence, const hal::output::DecodedPose& pose);
  bool close();  // false if any write failed
  uint64_t rows() const { return rows_; }
  uint64_t skipped() const { return skipped_; }

 private:
  std::FILE* file_ = nullptr;
  bool vertices_ = false;
  bool have_header_ = false;
  uint32_t vertex_count_ = 0;
  uint32_t input_count_ = 0;
  uint64_t rows_ = 0;
  uint64_t skipped_ = 0;
};

}  // namespace sinew::receiver
