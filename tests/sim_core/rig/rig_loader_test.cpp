// The valid blob loads into an arena of exactly the reported size, without
// allocating; versioning and the CRC-32C check value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "sample_rig.hpp"
#include "sim_core/rig/crc32c.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::test {
namespace {

using rig::LoadError;

TEST(RigCrc32c, CheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(rig::crc32c(0, reinterpret_cast<const uint8_t*>(check), 9), 0xE3069283u);
}

TEST(RigCrc32c, ContinuesAcrossChunks) {
  const char* check = "123456789";
  const auto* p = reinterpret_cast<const uint8_t*>(check);
  EXPECT_EQ(rig::crc32c(rig::crc32c(0, p, 4), p + 4, 5), 0xE3069283u);
}

// A section id is a fourcc: its little-endian bytes spell the name the
// format documents and the loader's messages use.
std::string fourcc(uint32_t id) {
  char text[5] = {};
  std::memcpy(text, &id, 4);
  return text;
}

TEST(RigFormat, MagicSpellsSNRG) { EXPECT_EQ(fourcc(rig::kMagic), "SNRG"); }

TEST(RigFormat, SectionIdsSpellTheirNames) {
  EXPECT_EQ(fourcc(rig::kSectionJoints), "JNTS");
  EXPECT_EQ(fourcc(rig::kSectionNames), "NAME");
  EXPECT_EQ(fourcc(rig::kSectionSynergies), "SYNR");
  EXPECT_EQ(fourcc(rig::kSectionPalette), "PALT");
  EXPECT_EQ(fourcc(rig::kSectionPositions), "VPOS");
  EXPECT_EQ(fourcc(rig::kSectionNormals), "VNRM");
  EXPECT_EQ(fourcc(rig::kSectionInfluenceJoints), "INFJ");
  EXPECT_EQ(fourcc(rig::kSectionInfluenceWeights), "INFW");
  EXPECT_EQ(fourcc(rig::kSectionVertexMethod), "METH");
  EXPECT_EQ(fourcc(rig::kSectionTriangles), "TRIS");
  EXPECT_EQ(fourcc(rig::kSectionPrimitives), "PRIM");
}

TEST(RigLoader, ValidBlobLoadsIntoArenaOfExactlyTheReportedSize) {
  const Blob blob = compile_sample();
  size_t arena_bytes = 0;
  const rig::LoadStatus v = rig::rig_validate(blob.data(), blob.size(), &arena_bytes);
  ASSERT_TRUE(v.ok()) << v.message;
  // The arena holds every known section, padded: the blob minus header and table.
  const rig::FileHeader h = blob.header();
  EXPECT_EQ(arena_bytes, h.total_size - sizeof(rig::FileHeader) - h.section_count * sizeof(rig::SectionEntry));

  // Exactly arena_bytes on the heap, so ASan sees any write past the end.
  auto arena = std::make_unique<uint64_t[]>(arena_bytes / 8);
  rig::Rig r;
  const rig::LoadStatus st = rig::rig_init(blob.data(), blob.size(), arena.get(), arena_bytes, &r);
  ASSERT_TRUE(st.ok()) << st.message;
  EXPECT_EQ(st.message[0], '\0');

  rig::Rig small;
  const rig::LoadStatus too_small = rig::rig_init(blob.data(), blob.size(), arena.get(), arena_bytes - 8, &small);
  EXPECT_EQ(too_small.error, LoadError::kArenaTooSmall);
  EXPECT_NE(std::string(too_small.message).find("arena"), std::string::npos) << too_small.message;
}

TEST(RigLoader, LoadedRigMatchesTheSpecAndOutlivesTheBlob) {
  const rigc::RigSpec spec = sample_rig_spec();
  auto blob = std::make_unique<Blob>(compile_sample());
  size_t arena_bytes = 0;
  ASSERT_TRUE(rig::rig_validate(blob->data(), blob->size(), &arena_bytes).ok());
  std::vector<uint64_t> arena(arena_bytes / 8);
  rig::Rig r;
  ASSERT_TRUE(rig::rig_init(blob->data(), blob->size(), arena.data(), arena_bytes, &r).ok());
  blob.reset();  // rig_init copied everything it needs

  EXPECT_EQ(r.joint_count(), 3u);
  EXPECT_EQ(r.vertex_count(), 20u);
  EXPECT_EQ(r.input_count, 4u);
  EXPECT_EQ(r.influences_per_vertex, 3u);
  EXPECT_EQ(r.synergies.size(), 1u);
  EXPECT_EQ(r.palette.size(), 3u);
  EXPECT_EQ(r.triangles.size(), 3 * spec.triangles.size());
  ASSERT_EQ(r.primitives.size(), 1u);
  EXPECT_EQ(r.primitives[0].vertex_count, 20u);
  EXPECT_TRUE(r.any_dual_quaternion);
  ASSERT_EQ(r.names.size(), 3u);
  EXPECT_STREQ(r.names[2], "tip");
  EXPECT_EQ(r.joints[2].parent, 1);
  EXPECT_EQ(r.joints[1].first_input, 1u);
  EXPECT_EQ(r.joints[1].dof_count, 2u);
  for (uint32_t v = 0; v < r.vertex_count(); ++v) {
    int64_t sum = 0;
    for (uint32_t k = 0; k < 3; ++k) sum += r.influence_weight[v * 3 + k];
    EXPECT_EQ(sum, fx::kUnitOne) << "vertex " << v;
  }
  for (int c = 0; c < 3; ++c) EXPECT_EQ(r.normal[c].size(), 20u);
}

TEST(RigLoader, ValidateAndInitNeverAllocate) {
  const Blob blob = compile_sample();
  std::vector<uint64_t> arena(blob.size() / 8);
  Blob corrupt = blob;
  corrupt.data()[100] ^= 0xFF;
  rig::Rig r;
  size_t arena_bytes = 0;

  AllocationCounter counter;
  const bool valid = rig::rig_validate(blob.data(), blob.size(), &arena_bytes).ok();
  const bool loaded = rig::rig_init(blob.data(), blob.size(), arena.data(), arena.size() * 8, &r).ok();
  const bool rejected = !rig::rig_validate(corrupt.data(), corrupt.size(), &arena_bytes).ok();
  const uint64_t allocations = counter.allocations();

  EXPECT_TRUE(valid && loaded && rejected);
  EXPECT_EQ(allocations, 0u);
}

TEST(RigLoader, RejectsMisalignedBlobPointer) {
  const Blob blob = compile_sample();
  std::vector<uint64_t> storage(blob.size() / 8 + 2);
  uint8_t* shifted = reinterpret_cast<uint8_t*>(storage.data()) + 4;
  std::memcpy(shifted, blob.data(), blob.size());
  size_t arena_bytes = 0;
  const rig::LoadStatus st = rig::rig_validate(shifted, blob.size(), &arena_bytes);
  EXPECT_EQ(st.error, LoadError::kMisaligned) << st.message;
  EXPECT_NE(std::string(st.message).find("aligned"), std::string::npos) << st.message;
}

TEST(RigLoader, RejectsMisalignedOrMissingArena) {
  const Blob blob = compile_sample();
  std::vector<uint64_t> arena(blob.size() / 8 + 1);
  rig::Rig r;
  void* odd = reinterpret_cast<uint8_t*>(arena.data()) + 4;
  EXPECT_EQ(rig::rig_init(blob.data(), blob.size(), odd, blob.size(), &r).error, LoadError::kArenaTooSmall);
  EXPECT_EQ(rig::rig_init(blob.data(), blob.size(), nullptr, blob.size(), &r).error, LoadError::kArenaTooSmall);
}

TEST(RigLoader, NullBlobIsTruncated) {
  size_t arena_bytes = 0;
  EXPECT_EQ(rig::rig_validate(nullptr, 4096, &arena_bytes).error, LoadError::kTruncated);
}

TEST(RigLoader, SkeletonWithoutSkinLoads) {
  rigc::RigSpec spec = sample_rig_spec();
  spec.vertices.clear();
  spec.triangles.clear();
  spec.primitives.clear();
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(rigc::compile_rig(spec, &bytes, &report, &error)) << error;
  const Blob blob(bytes);
  size_t arena_bytes = 0;
  ASSERT_TRUE(rig::rig_validate(blob.data(), blob.size(), &arena_bytes).ok());
  std::vector<uint64_t> arena(arena_bytes / 8);
  rig::Rig r;
  const rig::LoadStatus st = rig::rig_init(blob.data(), blob.size(), arena.data(), arena_bytes, &r);
  ASSERT_TRUE(st.ok()) << st.message;
  EXPECT_EQ(r.joint_count(), 3u);
  EXPECT_EQ(r.vertex_count(), 0u);
  EXPECT_TRUE(r.triangles.empty());
}

TEST(RigLoaderVersion, NewerMinorWithUnknownSectionIsAccepted) {
  const Blob base = compile_sample();
  rig::FileHeader h = base.header();
  h.version_minor = rig::kVersionMinor + 1;
  std::vector<Section> sections = sections_of(base);
  // An unknown section in the middle and one at the end, of odd sizes.
  sections.insert(sections.begin() + 3, Section{0x54584554u /* "TEXT" */, std::vector<uint8_t>(13, 0xAB)});
  sections.push_back(Section{0x31545845u /* "EXT1" */, std::vector<uint8_t>(5, 0xCD)});
  const Blob newer = assemble(h, sections);

  size_t arena_bytes = 0;
  const rig::LoadStatus st = rig::rig_validate(newer.data(), newer.size(), &arena_bytes);
  ASSERT_TRUE(st.ok()) << st.message;
  size_t base_arena = 0;
  ASSERT_TRUE(rig::rig_validate(base.data(), base.size(), &base_arena).ok());
  EXPECT_EQ(arena_bytes, base_arena);  // unknown sections are skipped, not copied
  std::vector<uint64_t> arena(arena_bytes / 8);
  rig::Rig r;
  ASSERT_TRUE(rig::rig_init(newer.data(), newer.size(), arena.data(), arena_bytes, &r).ok());
  EXPECT_EQ(r.joint_count(), 3u);
  EXPECT_EQ(r.vertex_count(), 20u);
}

TEST(RigLoaderVersion, ReorderedSectionsAreAccepted) {
  const Blob base = compile_sample();
  std::vector<Section> sections = sections_of(base);
  std::reverse(sections.begin(), sections.end());
  const Blob reordered = assemble(base.header(), sections);
  size_t arena_bytes = 0;
  const rig::LoadStatus st = rig::rig_validate(reordered.data(), reordered.size(), &arena_bytes);
  EXPECT_TRUE(st.ok()) << st.message;
}

TEST(RigLoaderVersion, OptionalSectionsMayBeAbsent) {
  const Blob base = compile_sample();
  std::vector<Section> sections;
  for (const Section& s : sections_of(base))
    if (s.id != rig::kSectionNames && s.id != rig::kSectionNormals) sections.push_back(s);
  const Blob lean = assemble(base.header(), sections);
  size_t arena_bytes = 0;
  ASSERT_TRUE(rig::rig_validate(lean.data(), lean.size(), &arena_bytes).ok());
  std::vector<uint64_t> arena(arena_bytes / 8);
  rig::Rig r;
  ASSERT_TRUE(rig::rig_init(lean.data(), lean.size(), arena.data(), arena_bytes, &r).ok());
  EXPECT_TRUE(r.names.empty());
  EXPECT_TRUE(r.normal[0].empty());
}

}  // namespace
}  // namespace sinew::test
