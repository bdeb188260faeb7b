// The layer sections' descriptors (sim_core/<layer>/<layer>_section.hpp),
// which the runtime loader and the rig compiler's writer both read: each is
// well formed, the sections a rig compiler writes match them array for
// array, and a section that differs from its descriptor by one array or one
// element size is refused, naming what differs.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>

#include "sim_core/pipeline/layer_format.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace {

namespace pl = sinew::pipeline;
namespace ly = sinew::layer;

TEST(SectionDescriptors, EveryDescriptorIsWellFormed) {
  std::set<uint32_t> ids;
  for (const ly::SectionDescriptor* d : pl::kLayerSections) {
    ASSERT_NE(d, nullptr);
    EXPECT_TRUE(ids.insert(d->id).second) << d->name;
    EXPECT_EQ(std::memcmp(&d->id, d->name, 4), 0) << "the id is the name's four characters: " << d->name;
    EXPECT_EQ(pl::find_layer_section(d->id), d);
    std::set<std::string> names;
    for (const ly::SectionArray& a : d->arrays) {
      ASSERT_NE(a.name, nullptr) << d->name << ": an array without a name (a table shorter than its count)";
      EXPECT_TRUE(names.insert(a.name).second) << d->name << "." << a.name;
      EXPECT_GT(a.element_size, 0u) << d->name << "." << a.name;
      EXPECT_GT(a.max_count, 0u) << d->name << "." << a.name;
    }
    ASSERT_FALSE(d->versions.empty()) << d->name;
    EXPECT_EQ(d->versions[0].version, ly::kLayerSectionVersion) << d->name;
    for (size_t i = 0; i < d->versions.size(); ++i) {
      const ly::SectionVersion& v = d->versions[i];
      EXPECT_LE(v.array_count, d->arrays.size()) << d->name << " version " << v.version;
      EXPECT_EQ(d->find(v.version), &v);
      if (i > 0) {
        EXPECT_GT(v.version, d->versions[i - 1].version) << d->name;
        EXPECT_GE(v.array_count, d->versions[i - 1].array_count) << d->name << ": a version only appends arrays";
      }
    }
    EXPECT_EQ(d->versions.back().array_count, d->arrays.size()) << d->name << ": the newest version has every array";
  }
  for (uint32_t id :
       {sinew::sph::kSectionSphJoint, sinew::metaballs::kSectionMetaballs, sinew::muscle::kSectionMuscles,
        sinew::elastic_skin::kSectionElasticSkin, sinew::barnet::kSectionBarnet, pl::kSectionExternalInputs})
    EXPECT_NE(pl::find_layer_section(id), nullptr) << std::hex << id;
}

// Every layer section of a compiled rig, read back field by field against
// its descriptor: what the writer wrote is what the loader expects.
void expect_sections_match_descriptors(const std::vector<uint8_t>& bytes, size_t* checked) {
  sinew::rig::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  for (uint32_t i = 0; i < h.section_count; ++i) {
    sinew::rig::SectionEntry e;
    std::memcpy(&e, bytes.data() + h.section_table_offset + i * sizeof(e), sizeof(e));
    const ly::SectionDescriptor* d = pl::find_layer_section(e.id);
    if (d == nullptr) continue;  // a core section
    ly::LayerSectionHeader sh;
    std::memcpy(&sh, bytes.data() + e.offset, sizeof(sh));
    const ly::SectionVersion* v = d->find(sh.layer_version);
    ASSERT_NE(v, nullptr) << d->name << " version " << sh.layer_version;
    EXPECT_EQ(sh.params_size, v->params_size) << d->name;
    ASSERT_EQ(sh.array_count, v->array_count) << d->name;
    const size_t table = e.offset + sizeof(sh) + ((sh.params_size + 7u) & ~7u);
    for (uint32_t a = 0; a < sh.array_count; ++a) {
      ly::LayerArrayEntry entry;
      std::memcpy(&entry, bytes.data() + table + a * sizeof(entry), sizeof(entry));
      EXPECT_EQ(entry.element_size, d->arrays[a].element_size) << d->name << "." << d->arrays[a].name;
    }
    ++*checked;
  }
}

TEST(SectionDescriptors, TheBuiltInRigsSectionsMatchTheirDescriptors) {
  size_t checked = 0;
  for (const char* name : {"arm", "hand"}) {
    std::string error;
    auto rig = sinew::test::builtin_with_layers(name, &error);
    ASSERT_NE(rig, nullptr) << name << ": " << error;
    expect_sections_match_descriptors(rig->bytes, &checked);
  }
  EXPECT_GE(checked, 5u);  // the arm alone carries SPHJ, MBAL, MUSC, SKIN, BNET
}

// One array more than the version declares, as a writer that added a field
// the descriptor lacks would write it: refused at array_count. An element
// size other than the descriptor's: refused naming the array.
TEST(SectionDescriptors, ASectionThatDiffersFromItsDescriptorIsRefusedNamed) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const size_t at = sinew::test::section_offset(arm->bytes, sinew::barnet::kSectionBarnet);
  ASSERT_NE(at, 0u);
  ly::LayerSectionHeader sh;
  std::memcpy(&sh, arm->bytes.data() + at, sizeof(sh));
  {
    sinew::test::LoadedLayers edited;
    edited.bytes = arm->bytes;
    const uint32_t more = sh.array_count + 1;
    std::memcpy(edited.bytes.data() + at + offsetof(ly::LayerSectionHeader, array_count), &more, 4);
    sinew::test::fix_crc(&edited.bytes);
    std::string error;
    EXPECT_FALSE(edited.load(&error));
    EXPECT_NE(error.find("BNET#0.array_count: does not match this layer's arrays"), std::string::npos) << error;
  }
  {
    sinew::test::LoadedLayers edited;
    edited.bytes = arm->bytes;
    const size_t table = at + sizeof(sh) + ((sh.params_size + 7u) & ~7u);
    const size_t nodes = table + 1 * sizeof(ly::LayerArrayEntry) + offsetof(ly::LayerArrayEntry, element_size);
    const uint32_t wrong = uint32_t{sizeof(sinew::barnet::NodeRecord)} + 4;
    std::memcpy(edited.bytes.data() + nodes, &wrong, 4);
    sinew::test::fix_crc(&edited.bytes);
    std::string error;
    EXPECT_FALSE(edited.load(&error));
    EXPECT_NE(error.find("BNET#0.nodes: element size differs"), std::string::npos) << error;
  }
}

}  // namespace
