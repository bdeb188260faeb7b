// Targeted corruption: one field patched, the CRC recomputed so the check
// behind it is reached, then the exact LoadError and a message naming the
// section and field ("rig blob: JNTS[1].parent: ...").
#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "sample_rig.hpp"

namespace sinew::test {
namespace {

using rig::FileHeader;
using rig::JointRecord;
using rig::LoadError;
using rig::SectionEntry;

struct FieldCase {
  const char* name;
  std::function<void(Blob&)> patch;
  LoadError error;
  const char* where;   // expected in the message: section[index].field
  bool reseal = true;  // false: the test is of a check made before the CRC
};

std::ostream& operator<<(std::ostream& os, const FieldCase& c) { return os << c.name; }

auto patch_header(std::function<void(FileHeader&)> edit) {
  return [edit](Blob& b) {
    FileHeader h = b.header();
    edit(h);
    b.set_header(h);
  };
}

auto patch_entry(uint32_t id, std::function<void(SectionEntry&)> edit) {
  return [id, edit](Blob& b) {
    const size_t at = b.entry_offset(id);
    SectionEntry e = b.read<SectionEntry>(at);
    edit(e);
    b.write(at, e);
  };
}

auto patch_joint(uint32_t index, std::function<void(JointRecord&)> edit) {
  return [index, edit](Blob& b) {
    JointRecord r = b.read<JointRecord>(joint_offset(b, index));
    edit(r);
    b.write(joint_offset(b, index), r);
  };
}

// Element `index` (of type T) of section `id` set to `value`.
template <typename T>
auto element(uint32_t id, size_t index, T value) {
  return [id, index, value](Blob& b) { b.write(b.section_offset(id) + index * sizeof(T), value); };
}

// Adds `delta` to element `index` of a section of int32 values.
auto add_i32(uint32_t id, size_t index, int32_t delta) {
  return [id, index, delta](Blob& b) {
    const size_t at = b.section_offset(id) + index * 4;
    b.write(at, b.read<int32_t>(at) + delta);
  };
}

constexpr uint32_t kK = 3;  // influences per vertex of the sample rig
constexpr int32_t kOne = fx::kUnitOne;

std::vector<FieldCase> header_cases() {
  return {
      {"BadMagic", patch_header([](FileHeader& h) { h.magic ^= 1; }), LoadError::kBadMagic, "header.magic"},
      {"MajorVersion3", patch_header([](FileHeader& h) { h.version_major = 3; }), LoadError::kBadVersion,
       "header.version_major"},
      {"MajorVersion0", patch_header([](FileHeader& h) { h.version_major = 0; }), LoadError::kBadVersion,
       "header.version_major"},
      {"HeaderSize", patch_header([](FileHeader& h) { h.header_size = 63; }), LoadError::kBadHeader,
       "header.header_size"},
      {"TotalSizeNotMultipleOf8", patch_header([](FileHeader& h) { h.total_size -= 4; }), LoadError::kBadHeader,
       "header.total_size", false},
      {"TotalSizeBelowHeader", patch_header([](FileHeader& h) { h.total_size = 56; }), LoadError::kBadHeader,
       "header.total_size", false},
      {"TotalSizeBeyondBlob", patch_header([](FileHeader& h) { h.total_size += 8; }), LoadError::kTruncated,
       "header.total_size", false},
      {"CrcMismatch", patch_header([](FileHeader& h) { h.crc32c ^= 1; }), LoadError::kChecksum, "header.crc32c", false},
      {"LengthExponentAbove16", patch_header([](FileHeader& h) { h.length_exponent = 17; }), LoadError::kBadValue,
       "header.length_exponent"},
      {"LengthExponentBelowMinus16", patch_header([](FileHeader& h) { h.length_exponent = -17; }), LoadError::kBadValue,
       "header.length_exponent"},
      {"JointCountZero", patch_header([](FileHeader& h) { h.joint_count = 0; }), LoadError::kBadValue,
       "header.joint_count"},
      {"SkinWithoutInfluences", patch_header([](FileHeader& h) { h.influences_per_vertex = 0; }), LoadError::kBadValue,
       "header.influences_per_vertex"},
      {"SkinWithoutPalette", patch_header([](FileHeader& h) { h.palette_count = 0; }), LoadError::kBadValue,
       "header.influences_per_vertex"},
      // One past each documented maximum.
      {"JointsBeyondMax", patch_header([](FileHeader& h) { h.joint_count = rig::kMaxJoints + 1; }), LoadError::kLimit,
       "header.joint_count"},
      {"PaletteBeyondMax", patch_header([](FileHeader& h) { h.palette_count = rig::kMaxPalette + 1; }),
       LoadError::kLimit, "header.palette_count"},
      {"VerticesBeyondMax", patch_header([](FileHeader& h) { h.vertex_count = rig::kMaxVertices + 1; }),
       LoadError::kLimit, "header.vertex_count"},
      {"TrianglesBeyondMax", patch_header([](FileHeader& h) { h.triangle_count = rig::kMaxTriangles + 1; }),
       LoadError::kLimit, "header.triangle_count"},
      {"InfluencesBeyondMax", patch_header([](FileHeader& h) { h.influences_per_vertex = rig::kMaxInfluences + 1; }),
       LoadError::kLimit, "header.influences_per_vertex"},
      {"InputsBeyondMax", patch_header([](FileHeader& h) { h.input_count = rig::kMaxInputs + 1; }), LoadError::kLimit,
       "header.input_count"},
      {"SynergiesBeyondMax", patch_header([](FileHeader& h) { h.synergy_count = rig::kMaxSynergies + 1; }),
       LoadError::kLimit, "header.synergy_count"},
      {"PrimitivesBeyondMax", patch_header([](FileHeader& h) { h.primitive_count = rig::kMaxPrimitives + 1; }),
       LoadError::kLimit, "header.primitive_count"},
      {"SectionsBeyondMax", patch_header([](FileHeader& h) { h.section_count = rig::kMaxSections + 1; }),
       LoadError::kLimit, "header.section_count"},
  };
}

std::vector<FieldCase> table_cases() {
  using rig::kSectionJoints, rig::kSectionTriangles, rig::kSectionPrimitives;
  return {
      {"TableOffsetMisaligned", patch_header([](FileHeader& h) { h.section_table_offset += 4; }),
       LoadError::kSectionTable, "section table.offset"},
      {"TableOffsetInsideHeader", patch_header([](FileHeader& h) { h.section_table_offset = 32; }),
       LoadError::kSectionTable, "section table.offset"},
      {"TableBeyondBlob", patch_header([](FileHeader& h) { h.section_table_offset = h.total_size - 8; }),
       LoadError::kSectionTable, "section table.offset"},
      {"SectionOffsetMisaligned", patch_entry(kSectionJoints, [](SectionEntry& e) { e.offset += 4; }),
       LoadError::kSectionTable, "section table[0].offset"},
      {"SectionOffsetBeyondBlob", patch_entry(kSectionPrimitives, [](SectionEntry& e) { e.offset = 1u << 30; }),
       LoadError::kSectionTable, "section table[10].offset"},
      {"SectionEndBeyondBlob", patch_entry(kSectionPrimitives, [](SectionEntry& e) { e.size = 0xFFFFFFF8u; }),
       LoadError::kSectionTable, "section table[10].offset"},
      {"SectionOverlapsTable", patch_entry(kSectionJoints, [](SectionEntry& e) { e.offset = sizeof(FileHeader); }),
       LoadError::kSectionTable, "section table[0].offset"},
      {"DuplicateSection", patch_entry(rig::kSectionNames, [](SectionEntry& e) { e.id = kSectionJoints; }),
       LoadError::kSectionTable, "section table[1].id"},
      {"MissingJoints", patch_entry(kSectionJoints, [](SectionEntry& e) { e.id = 0x58585858u; }),
       LoadError::kMissingSection, "JNTS"},
      {"MissingWeights", patch_entry(rig::kSectionInfluenceWeights, [](SectionEntry& e) { e.id = 0x58585858u; }),
       LoadError::kMissingSection, "INFW"},
      {"MissingTriangles", patch_entry(kSectionTriangles, [](SectionEntry& e) { e.id = 0x58585858u; }),
       LoadError::kMissingSection, "TRIS"},
      {"JointsSizeWrong", patch_entry(kSectionJoints, [](SectionEntry& e) { e.size -= 128; }), LoadError::kSectionSize,
       "JNTS.size"},
      {"WeightsSizeWrong", patch_entry(rig::kSectionInfluenceWeights, [](SectionEntry& e) { e.size -= 8; }),
       LoadError::kSectionSize, "INFW.size"},
      {"MethodSizeUnpadded", patch_entry(rig::kSectionVertexMethod, [](SectionEntry& e) { e.size = 20; }),
       LoadError::kSectionSize, "METH.size"},
      {"NamesSizeWrong", patch_entry(rig::kSectionNames, [](SectionEntry& e) { e.size -= 32; }),
       LoadError::kSectionSize, "NAME.size"},
      {"TriangleCountDisagrees", patch_header([](FileHeader& h) { h.triangle_count -= 1; }), LoadError::kSectionSize,
       "TRIS.size"},
      // rig.hpp documents kSectionTable for overlapping entries: VNRM aliasing
      // VPOS (same size, normals are not range-checked) must be refused.
      {"SectionsOverlap",
       [](Blob& b) {
         const uint32_t positions = static_cast<uint32_t>(b.section_offset(rig::kSectionPositions));
         patch_entry(rig::kSectionNormals, [positions](SectionEntry& e) { e.offset = positions; })(b);
       },
       LoadError::kSectionTable, "section table"},
  };
}

std::vector<FieldCase> joint_cases() {
  return {
      {"ParentSelf", patch_joint(1, [](JointRecord& r) { r.parent = 1; }), LoadError::kBadIndex, "JNTS[1].parent"},
      {"ParentForward", patch_joint(1, [](JointRecord& r) { r.parent = 2; }), LoadError::kBadIndex, "JNTS[1].parent"},
      {"ParentOutOfRange", patch_joint(2, [](JointRecord& r) { r.parent = 100; }), LoadError::kBadIndex,
       "JNTS[2].parent"},
      {"ParentBelowMinusOne", patch_joint(0, [](JointRecord& r) { r.parent = -2; }), LoadError::kBadIndex,
       "JNTS[0].parent"},
      {"DofCount4", patch_joint(2, [](JointRecord& r) { r.dof_count = 4; }), LoadError::kBadValue, "JNTS[2].dof_count"},
      {"DofKindUnknown", patch_joint(1, [](JointRecord& r) { r.dof_kind = 2; }), LoadError::kBadValue,
       "JNTS[1].dof_kind"},
      {"FirstInputBeyondInputs", patch_joint(2, [](JointRecord& r) { r.first_input = 4; }), LoadError::kBadIndex,
       "JNTS[2].first_input"},
      {"LastInputBeyondInputs", patch_joint(1, [](JointRecord& r) { r.first_input = 3; }), LoadError::kBadIndex,
       "JNTS[1].first_input"},
      {"RestRotationNotUnit", patch_joint(2, [](JointRecord& r) { r.rest_rotation[0] = 0; }), LoadError::kBadValue,
       "JNTS[2].rest_rotation"},
      {"RestRotationZero", patch_joint(0, [](JointRecord& r) { r.rest_rotation[0] = 0; }), LoadError::kBadValue,
       "JNTS[0].rest_rotation"},
      // Components far outside [-1, 1]: the squared norm must not overflow int64.
      {"RestRotationExtreme",
       patch_joint(0, [](JointRecord& r) { r.rest_rotation[0] = r.rest_rotation[1] = INT32_MIN; }),
       LoadError::kBadValue, "JNTS[0].rest_rotation"},
      {"DofAxisZero",
       patch_joint(1, [](JointRecord& r) { r.dof_axis[1][0] = r.dof_axis[1][1] = r.dof_axis[1][2] = 0; }),
       LoadError::kBadValue, "JNTS[1].dof_axis"},
      {"DofAxisExtreme", patch_joint(1, [](JointRecord& r) { r.dof_axis[0][0] = r.dof_axis[0][1] = INT32_MIN; }),
       LoadError::kBadValue, "JNTS[1].dof_axis"},
      {"DofMinAboveMax", patch_joint(1, [](JointRecord& r) { r.dof_min[1] = r.dof_max[1] + 1; }), LoadError::kBadValue,
       "JNTS[1].dof_min"},
      {"NameNotTerminated",
       [](Blob& b) {
         const size_t at = b.section_offset(rig::kSectionNames) + rig::kNameBytes;
         for (size_t i = 0; i < rig::kNameBytes; ++i) b.data()[at + i] = 'a';
       },
       LoadError::kBadValue, "NAME[1].name"},
  };
}

std::vector<FieldCase> record_cases() {
  using rig::kSectionSynergies, rig::kSectionPalette;
  // SynergyRecord: source_input @0, target_joint @2, target_dof @4.
  // PaletteRecord: joint @0, inverse_bind.m[0][0] @4.
  auto at = [](uint32_t id, size_t offset, auto value) {
    return [id, offset, value](Blob& b) { b.write(b.section_offset(id) + offset, value); };
  };
  const size_t palette = sizeof(rig::PaletteRecord);
  return {
      {"SynergySourceBeyondInputs", at(kSectionSynergies, 0, uint16_t{4}), LoadError::kBadIndex,
       "SYNR[0].source_input"},
      {"SynergyTargetJointBeyondJoints", at(kSectionSynergies, 2, uint16_t{3}), LoadError::kBadIndex,
       "SYNR[0].target_joint"},
      {"SynergyTargetDofBeyondDofs", at(kSectionSynergies, 4, uint8_t{1}), LoadError::kBadIndex, "SYNR[0].target_dof"},
      {"PaletteJointOutOfRange", at(kSectionPalette, palette, uint32_t{3}), LoadError::kBadIndex, "PALT[1].joint"},
      {"InverseBindEntryTooLarge", at(kSectionPalette, 2 * palette + 4, int32_t{(1 << 30) + 1}), LoadError::kBadValue,
       "PALT[2].inverse_bind"},
      {"InverseBindEntryTooNegative", at(kSectionPalette, 4 + 4 * 4, int32_t{-(1 << 30) - 1}), LoadError::kBadValue,
       "PALT[0].inverse_bind"},
  };
}

std::vector<FieldCase> skin_cases() {
  using rig::kSectionInfluenceJoints, rig::kSectionInfluenceWeights;
  return {
      {"InfluencePaletteOutOfRange", element(kSectionInfluenceJoints, 4 * kK + 1, uint16_t{3}), LoadError::kBadIndex,
       "INFJ[4].palette_index"},
      {"NegativeWeight",
       [](Blob& b) {  // moves w0 + 1 to the next slot: the sum stays 2^30, the sign check must fire
         const size_t w0 = b.section_offset(kSectionInfluenceWeights) + 5 * kK * 4;
         b.write(w0 + 4, b.read<int32_t>(w0 + 4) + b.read<int32_t>(w0) + 1);
         b.write(w0, int32_t{-1});
       },
       LoadError::kBadValue, "INFW[5].weight"},
      {"WeightAboveOne", element(kSectionInfluenceWeights, 2 * kK, kOne + 1), LoadError::kBadValue, "INFW[2].weight"},
      {"WeightsSumOneShort", add_i32(kSectionInfluenceWeights, 6 * kK, -1), LoadError::kBadValue, "INFW[6].weight"},
      {"WeightsSumOneOver", add_i32(kSectionInfluenceWeights, 7 * kK + 2, 1), LoadError::kBadValue, "INFW[7].weight"},
      {"MethodUnknown", element(rig::kSectionVertexMethod, 7, uint8_t{7}), LoadError::kBadValue, "METH[7].method"},
      {"TriangleIndexOutOfRange", element(rig::kSectionTriangles, 3 * 3 + 1, uint32_t{20}), LoadError::kBadIndex,
       "TRIS[3].vertex"},
      {"PrimitiveRangeBeyondVertices", element(rig::kSectionPrimitives, 1, uint32_t{21}), LoadError::kBadIndex,
       "PRIM[0].vertex_count"},
      {"PrimitiveRangeWraps",
       [](Blob& b) {
         element(rig::kSectionPrimitives, 0, uint32_t{0xFFFFFFFFu})(b);
         element(rig::kSectionPrimitives, 1, uint32_t{2})(b);
       },
       LoadError::kBadIndex, "PRIM[0].vertex_count"},
  };
}

std::vector<FieldCase> all_cases() {
  std::vector<FieldCase> all;
  for (auto make : {header_cases, table_cases, joint_cases, record_cases, skin_cases})
    for (FieldCase& c : make()) all.push_back(std::move(c));
  return all;
}

class RigFieldCorruption : public ::testing::TestWithParam<FieldCase> {};

TEST_P(RigFieldCorruption, RejectedWithExactErrorNamingTheField) {
  const FieldCase& c = GetParam();
  Blob blob = compile_sample();
  c.patch(blob);
  if (c.reseal) blob.reseal();
  size_t arena_bytes = 0;
  const rig::LoadStatus st = rig::rig_validate(blob.data(), blob.size(), &arena_bytes);
  EXPECT_EQ(st.error, c.error) << "got " << rig::load_error_name(st.error) << ": " << st.message;
  const std::string message = st.message;
  EXPECT_EQ(message.rfind("rig blob: ", 0), 0u) << message;
  EXPECT_NE(message.find(c.where), std::string::npos) << "expected '" << c.where << "' in: " << message;
  // rig_init validates the same way and leaves the arena untouched on failure.
  std::vector<uint64_t> arena(blob.size() / 8 + 1, 0x5A5A5A5A5A5A5A5Au);
  rig::Rig r;
  EXPECT_EQ(rig::rig_init(blob.data(), blob.size(), arena.data(), arena.size() * 8, &r).error, c.error);
  for (uint64_t w : arena) ASSERT_EQ(w, 0x5A5A5A5A5A5A5A5Au);
}

INSTANTIATE_TEST_SUITE_P(Fields, RigFieldCorruption, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<FieldCase>& p) { return std::string(p.param.name); });

TEST(RigFieldCorruption, UnpatchedSampleIsValid) {  // the cases above start from a valid blob
  const Blob blob = compile_sample();
  size_t arena_bytes = 0;
  const rig::LoadStatus st = rig::rig_validate(blob.data(), blob.size(), &arena_bytes);
  EXPECT_TRUE(st.ok()) << st.message;
}

}  // namespace
}  // namespace sinew::test
