// Frame log layout (docs/frame-formats.md): a 40-byte file header, then
// self-delimiting records, each [magic, payload length, checksum, payload].
// A record is intact only if its checksum matches, so a reader recovers every
// record written before a crash and stops at the torn one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "frame_shape.hpp"

namespace sinew::hal::output {

inline constexpr uint8_t kLogMagic[8] = {'S', 'I', 'N', 'E', 'W', 'L', 'O', 'G'};
inline constexpr uint16_t kLogVersion = 1;
inline constexpr size_t kLogHeaderBytes = 40;
inline constexpr uint32_t kLogFlagNormals = 1u << 0;

inline constexpr uint32_t kRecordMagic = 0x43455253u;  // bytes "SREC"
inline constexpr size_t kRecordHeaderBytes = 16;

void encode_log_header(const FrameShape& shape, uint8_t out[kLogHeaderBytes]);

// Parses and checks a file header; false with the reason in *why.
bool parse_log_header(std::span<const uint8_t> bytes, FrameShape* shape, std::string* why);

// Why two shapes differ, for refusing to append (empty when equal).
std::string describe_shape_mismatch(const FrameShape& log, const FrameShape& wanted);

// Fills the 16-byte record header for `payload`.
void encode_record_header(std::span<const uint8_t> payload, uint8_t out[kRecordHeaderBytes]);

// The checksum stored in a record header: XXH64 of its length field followed by the payload.
uint64_t record_checksum(const uint8_t length_field[4], std::span<const uint8_t> payload);

// Payload lengths a log of this shape can hold: with or without normals.
bool record_length_allowed(const FrameShape& shape, uint32_t payload_bytes);

// Largest record (header + payload) of this shape.
uint64_t max_record_bytes(const FrameShape& shape);

}  // namespace sinew::hal::output
