// Blind corruption: every truncation and every single-byte flip of the valid
// blob is rejected with a message, and never reads out of bounds (run under
// the dev preset's ASan/UBSan).
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <memory>

#include "sample_rig.hpp"

namespace sinew::test {
namespace {

using rig::LoadError;

TEST(RigCorruption, EveryTruncationIsRejected) {
  const Blob blob = compile_sample();
  ASSERT_GT(blob.size(), sizeof(rig::FileHeader));
  for (size_t length = 0; length < blob.size(); ++length) {
    // Exactly `length` bytes on the heap (malloc is 16-byte aligned), so
    // ASan reports any read past the truncated end.
    auto bytes = std::make_unique<uint8_t[]>(length);
    if (length > 0) std::memcpy(bytes.get(), blob.data(), length);
    size_t arena_bytes = 0;
    const rig::LoadStatus st = rig::rig_validate(bytes.get(), length, &arena_bytes);
    EXPECT_EQ(st.error, LoadError::kTruncated) << "length " << length << ": " << st.message;
    EXPECT_NE(st.message[0], '\0') << "length " << length;
    rig::Rig r;
    uint64_t arena[4];
    EXPECT_FALSE(rig::rig_init(bytes.get(), length, arena, sizeof(arena), &r).ok()) << "length " << length;
  }
}

TEST(RigCorruption, EverySingleByteFlipIsRejected) {
  const Blob blob = compile_sample();
  const size_t crc_at = offsetof(rig::FileHeader, crc32c);
  for (size_t at = 0; at < blob.size(); ++at) {
    Blob bad = blob;
    bad.data()[at] ^= 0xFF;
    size_t arena_bytes = 0;
    const rig::LoadStatus st = rig::rig_validate(bad.data(), bad.size(), &arena_bytes);
    ASSERT_FALSE(st.ok()) << "byte " << at;
    EXPECT_NE(st.message[0], '\0') << "byte " << at;
    // Magic, version, header_size and total_size are checked before the
    // CRC; from the crc field on, the CRC is what catches the flip.
    if (at >= crc_at) {
      EXPECT_EQ(st.error, LoadError::kChecksum) << "byte " << at << ": " << st.message;
    }
  }
}

TEST(RigCorruption, TrailingBytesBeyondTotalSizeAreIgnored) {
  const Blob blob = compile_sample();
  std::vector<uint8_t> longer(blob.data(), blob.data() + blob.size());
  longer.resize(blob.size() + 24, 0xEE);
  const Blob padded(longer);
  size_t arena_bytes = 0;
  const rig::LoadStatus st = rig::rig_validate(padded.data(), padded.size(), &arena_bytes);
  EXPECT_TRUE(st.ok()) << st.message;
}

}  // namespace
}  // namespace sinew::test
