// Frame log layout (docs/frame-formats.md): a 40-byte file header, then
// self-delimiting records, each [magic, payload length, checksum, payload].
// A record is intact only if its checksum matches, so a reader recovers every
// record written before a crash and stops at the torn one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "frame_shape.hpp"

namespace sinew::hal::output {

inline constexpr uint8_t kLogMagic[8] = {'S', 'I', 'N', 'E', 'W', 'L', 'O', 'G'};
inline constexpr uint16_t kLogVersion = 1;          // header, then records
inline constexpr uint16_t kLogVersionMetadata = 2;  // header, metadata block, then records
inline constexpr size_t kMaxLogMetadataBytes = 65536;
inline constexpr size_t kLogHeaderBytes = 40;
inline constexpr uint32_t kLogFlagNormals = 1u << 0;
inline constexpr uint32_t kLogFlagCompressed = 1u << 1;  // records are compressed (frame_compression.hpp)

inline constexpr uint32_t kRecordMagic = 0x43455253u;  // bytes "SREC"
inline constexpr size_t kRecordHeaderBytes = 16;

void encode_log_header(const FrameShape& shape, bool compressed, uint8_t out[kLogHeaderBytes]);

// Parses and checks a file header; false with the reason in *why. A version-2
// header sets *metadata_bytes (M, 1..kMaxLogMetadataBytes), else it is 0;
// *compressed says whether the records are compressed.
bool parse_log_header(std::span<const uint8_t> bytes, FrameShape* shape, std::string* why,
                      uint32_t* metadata_bytes = nullptr, bool* compressed = nullptr);

// Everything before the first record: the header, and for a version-2 log
// the metadata block (M bytes of text, then the XXH64 of those bytes), which
// describes the log's content (a recording names the run it records).
struct LogPreamble {
  FrameShape shape;
  std::string metadata;                       // empty: a version-1 log
  uint64_t records_offset = kLogHeaderBytes;  // where the first record starts
  bool compressed = false;                    // records compressed (frame_compression.hpp)
};

// The bytes of a preamble: a version-1 header alone when metadata is empty.
std::vector<uint8_t> encode_log_preamble(const FrameShape& shape, std::string_view metadata, bool compressed = false);

// Reads and checks a preamble from `fd` (file_size bytes); false with the
// reason in *why.
bool read_log_preamble(int fd, uint64_t file_size, LogPreamble* out, std::string* why);

// Why two shapes differ, for refusing to append (empty when equal).
std::string describe_shape_mismatch(const FrameShape& log, const FrameShape& wanted);

// Fills the 16-byte record header for `payload`.
void encode_record_header(std::span<const uint8_t> payload, uint8_t out[kRecordHeaderBytes]);

// The checksum stored in a record header: XXH64 of its length field followed by the payload.
uint64_t record_checksum(const uint8_t length_field[4], std::span<const uint8_t> payload);

// Payload lengths a log of this shape can hold: with or without normals; in
// a compressed log, any length from 2 (a kind byte and the smallest zstd
// frame) to the compressed bound of the largest payload.
bool record_length_allowed(const FrameShape& shape, uint32_t payload_bytes, bool compressed = false);

// Largest record (header + payload) of this shape.
uint64_t max_record_bytes(const FrameShape& shape, bool compressed = false);

}  // namespace sinew::hal::output
