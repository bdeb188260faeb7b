#include "frame_compression.hpp"

#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_initStaticCCtx: a context in memory sized at init
#include <zstd.h>

#include <algorithm>
#include <cstring>

namespace sinew::hal::output {

namespace {

// Splits n = payload.size() bytes into four byte planes of the n / 4 words
// (the word taken minus the previous payload's word when `previous` is
// given), then the n mod 4 last bytes (minus the previous ones).
void to_planes(const uint8_t* payload, const uint8_t* previous, size_t n, uint8_t* planes) {
  const size_t words = n / 4;
  for (size_t i = 0; i < words; ++i) {
    uint32_t w;
    std::memcpy(&w, payload + 4 * i, 4);
    if (previous != nullptr) {
      uint32_t p;
      std::memcpy(&p, previous + 4 * i, 4);
      w -= p;  // unsigned: modulo 2^32
    }
    for (size_t k = 0; k < 4; ++k) planes[k * words + i] = static_cast<uint8_t>(w >> (8 * k));
  }
  for (size_t j = 4 * words; j < n; ++j)
    planes[j] = static_cast<uint8_t>(payload[j] - (previous != nullptr ? previous[j] : 0));
}

// The inverse of to_planes.
void from_planes(const uint8_t* planes, const uint8_t* previous, size_t n, uint8_t* payload) {
  const size_t words = n / 4;
  for (size_t i = 0; i < words; ++i) {
    uint32_t w = 0;
    for (size_t k = 0; k < 4; ++k) w |= uint32_t{planes[k * words + i]} << (8 * k);
    if (previous != nullptr) {
      uint32_t p;
      std::memcpy(&p, previous + 4 * i, 4);
      w += p;
    }
    std::memcpy(payload + 4 * i, &w, 4);
  }
  for (size_t j = 4 * words; j < n; ++j)
    payload[j] = static_cast<uint8_t>(planes[j] + (previous != nullptr ? previous[j] : 0));
}

}  // namespace

uint64_t max_compressed_record_payload(uint64_t max_payload) { return 1 + ZSTD_COMPRESSBOUND(max_payload); }

bool FrameCompressor::init(size_t max_payload, int level, uint32_t key_every, std::string* error) {
  if (level < kMinCompressionLevel || level > kMaxCompressionLevel)
    return *error = "compression level " + std::to_string(level) + " is outside " +
                    std::to_string(kMinCompressionLevel) + ".." + std::to_string(kMaxCompressionLevel),
           false;
  if (key_every == 0) return *error = "key_every_frames must be at least 1", false;
  const size_t context = ZSTD_estimateCCtxSize(level);
  workspace_.assign(context / 8 + 1, 0);
  cctx_ = ZSTD_initStaticCCtx(workspace_.data(), workspace_.size() * 8);
  if (cctx_ == nullptr) return *error = "cannot set up the zstd compression context", false;
  // The record's own XXH64 guards the bytes; the content size stays in the
  // frame so that a reader can check it before decompressing.
  ZSTD_CCtx_setParameter(cctx_, ZSTD_c_compressionLevel, level);
  ZSTD_CCtx_setParameter(cctx_, ZSTD_c_checksumFlag, 0);
  ZSTD_CCtx_setParameter(cctx_, ZSTD_c_contentSizeFlag, 1);
  previous_.assign(max_payload, 0);
  planes_.assign(max_payload, 0);
  out_.assign(head_room + static_cast<size_t>(max_compressed_record_payload(max_payload)), 0);
  previous_bytes_ = 0;
  since_key_ = 0;
  key_every_ = key_every;
  level_ = level;
  return true;
}

std::span<uint8_t> FrameCompressor::encode(std::span<const uint8_t> payload) {
  const size_t n = payload.size();
  if (cctx_ == nullptr || n > planes_.size()) return {};
  const bool delta = previous_bytes_ == n && since_key_ < key_every_;
  to_planes(payload.data(), delta ? previous_.data() : nullptr, n, planes_.data());
  uint8_t* record = out_.data() + head_room;
  record[0] = delta ? kRecordKindDelta : kRecordKindKey;
  const size_t z = ZSTD_compress2(cctx_, record + 1, out_.size() - head_room - 1, planes_.data(), n);
  if (ZSTD_isError(z)) {
    restart();
    return {};
  }
  std::memcpy(previous_.data(), payload.data(), n);
  previous_bytes_ = n;
  since_key_ = delta ? since_key_ + 1 : 1;
  return {record, 1 + z};
}

FrameDecompressor::~FrameDecompressor() { ZSTD_freeDCtx(dctx_); }

uint64_t zstd_max_decoded_bytes(uint64_t compressed) {
  constexpr uint64_t kRatio = 128 * 1024 / 4;
  return compressed > UINT64_MAX / kRatio ? UINT64_MAX : compressed * kRatio;
}

bool FrameDecompressor::init(size_t max_payload, uint64_t compressed_bytes, std::string* error) {
  ZSTD_freeDCtx(dctx_);
  dctx_ = ZSTD_createDCtx();
  if (dctx_ == nullptr) return *error = "cannot set up the zstd decompression context", false;
  const size_t capacity =
      static_cast<size_t>(std::min<uint64_t>(max_payload, zstd_max_decoded_bytes(compressed_bytes)));
  // Buffers grow to the largest record read, not to the bound: a file's
  // bytes can bound records at 32 768 times their size.
  capacity_ = capacity;
  planes_.clear();
  payload_.clear();
  previous_bytes_ = 0;
  return true;
}

bool FrameDecompressor::decode(std::span<const uint8_t> record, std::span<const uint8_t>* payload, std::string* why) {
  if (dctx_ == nullptr) return *why = "no decompression context", false;
  if (record.size() < 2) return *why = "compressed record shorter than its kind byte and a zstd frame", false;
  const uint8_t kind = record[0];
  if (kind != kRecordKindKey && kind != kRecordKindDelta)
    return *why = "compressed record of unknown kind " + std::to_string(kind), false;
  const std::span<const uint8_t> frame = record.subspan(1);
  const unsigned long long size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    return *why = "compressed record is not a zstd frame with its content size", false;
  if (size > capacity_)
    return *why = "compressed record claims " + std::to_string(size) +
                  " bytes, more than the log's frames hold or its file's compressed bytes can decode to",
           false;
  const bool delta = kind == kRecordKindDelta;
  if (delta && previous_bytes_ != size)
    return *why = previous_bytes_ == 0 ? "delta record without a record before it"
                                       : "delta record after a record of another length",
           false;
  if (planes_.size() < size) {  // a delta never grows them: it has its key's size
    planes_.resize(static_cast<size_t>(size));
    payload_.resize(static_cast<size_t>(size));
  }
  const size_t got = ZSTD_decompressDCtx(dctx_, planes_.data(), static_cast<size_t>(size), frame.data(), frame.size());
  if (ZSTD_isError(got)) return *why = std::string("zstd: ") + ZSTD_getErrorName(got), false;
  if (got != size) return *why = "compressed record decodes to another size than it declares", false;
  // In place: word i reads only previous word i before writing it.
  from_planes(planes_.data(), delta ? payload_.data() : nullptr, got, payload_.data());
  previous_bytes_ = got;
  *payload = {payload_.data(), got};
  return true;
}

}  // namespace sinew::hal::output
