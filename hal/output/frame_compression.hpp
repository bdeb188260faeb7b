// Compressed frame-log records (docs/frame-formats.md, "Compressed records").
// A compressed record's payload is one kind byte followed by one zstd frame
// of the transformed pose payload:
//   - key (kind 0): the payload's little-endian 32-bit words split into four
//     byte planes (all first bytes, then all second bytes, ...), then the
//     last L mod 4 bytes as they are;
//   - delta (kind 1): each word minus the previous record's word, modulo
//     2^32, then the same planes; the last bytes minus the previous record's,
//     modulo 2^8.
// Consecutive frames of a moving mesh differ in the low bytes of each word
// only: the planes put the near-constant high bytes together, where zstd
// finds long runs (about 18x smaller than the raw frame on the arm at 1 kHz,
// against 1.3x for zstd on the raw frame). A delta follows the previous
// record of the same payload length; the writer makes a key of the first
// record it writes, of every key_every-th one, of one whose length differs
// from the previous one (normals on or off), and of the next one after a
// failed write. A reader decodes records in order, so a damaged record stops
// it there, as in an uncompressed log.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

struct ZSTD_CCtx_s;
struct ZSTD_DCtx_s;

namespace sinew::hal::output {

inline constexpr uint8_t kRecordKindKey = 0;
inline constexpr uint8_t kRecordKindDelta = 1;
inline constexpr int kMinCompressionLevel = 1;
inline constexpr int kMaxCompressionLevel = 19;

// Largest compressed record payload for pose payloads up to max_payload bytes.
uint64_t max_compressed_record_payload(uint64_t max_payload);

class FrameCompressor {
 public:
  FrameCompressor() = default;
  FrameCompressor(const FrameCompressor&) = delete;
  FrameCompressor& operator=(const FrameCompressor&) = delete;

  // Sizes every buffer, and zstd's workspace, for payloads up to max_payload
  // bytes: encode() never allocates. level in [kMinCompressionLevel,
  // kMaxCompressionLevel]; key_every >= 1.
  bool init(size_t max_payload, int level, uint32_t key_every, std::string* error);

  // The record payload (kind byte + zstd frame) of one pose payload, valid
  // until the next call, with `head_room` free bytes before it for the
  // caller's record header; empty if zstd failed (then the next is a key).
  std::span<uint8_t> encode(std::span<const uint8_t> payload);
  static constexpr size_t head_room = 16;

  // The next record is a key (after a record that did not reach the file).
  void restart() { previous_bytes_ = 0; }

 private:
  std::vector<uint64_t> workspace_;  // zstd's static compression context (8-byte aligned)
  ZSTD_CCtx_s* cctx_ = nullptr;
  std::vector<uint8_t> previous_, planes_, out_;
  size_t previous_bytes_ = 0;  // 0: no previous record, the next is a key
  uint32_t since_key_ = 0;
  uint32_t key_every_ = 1;
  int level_ = 1;
};

// The most `compressed` bytes of zstd frames can decode to (RFC 8878
// §3.1.1.2): a block yields at most 128 KiB and takes at least 4 bytes (a
// 3-byte header and one RLE byte), so at most 32 768 bytes a byte.
uint64_t zstd_max_decoded_bytes(uint64_t compressed);

// Host side (allocates at init, and grows its buffers to the largest record
// read, never beyond init's bound).
class FrameDecompressor {
 public:
  FrameDecompressor() = default;
  ~FrameDecompressor();
  FrameDecompressor(const FrameDecompressor&) = delete;
  FrameDecompressor& operator=(const FrameDecompressor&) = delete;

  // Buffers for records of at most `max_payload` bytes once decoded, and at
  // most what `compressed_bytes` of zstd frames can decode to (a header's
  // shape can claim gigabytes a short file never holds; see
  // zstd_max_decoded_bytes).
  bool init(size_t max_payload, uint64_t compressed_bytes, std::string* error);

  // The pose payload of one record payload, valid until the next call; false
  // with the reason if the record does not decode (a damaged record).
  bool decode(std::span<const uint8_t> record, std::span<const uint8_t>* payload, std::string* why);
  size_t capacity() const { return capacity_; }  // the largest decoded record it accepts

 private:
  ZSTD_DCtx_s* dctx_ = nullptr;
  std::vector<uint8_t> planes_, payload_;  // grown to the largest record decoded so far
  size_t capacity_ = 0;
  size_t previous_bytes_ = 0;
};

}  // namespace sinew::hal::output
