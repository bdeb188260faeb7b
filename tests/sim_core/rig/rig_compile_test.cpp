// compile_rig: each bad spec is refused with a message naming the item, and
// influence weights are renormalised to sum exactly 2^30.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <string>

#include "sample_rig.hpp"

namespace sinew::test {
namespace {

struct BadSpec {
  const char* name;
  std::function<void(rigc::RigSpec&)> edit;
  const char* where;  // expected in the error message
};

std::ostream& operator<<(std::ostream& os, const BadSpec& c) { return os << c.name; }

std::vector<BadSpec> bad_specs() {
  return {
      {"NoJoints", [](rigc::RigSpec& s) { s.joints.clear(); }, "no joints"},
      {"ParentAfterChild", [](rigc::RigSpec& s) { s.joints[2].parent = 2; }, "joint[2].parent"},
      {"ParentBeyondJoints", [](rigc::RigSpec& s) { s.joints[1].parent = 7; }, "joint[1].parent"},
      {"FourDofs", [](rigc::RigSpec& s) { s.joints[1].dofs.resize(4); }, "joint[1].dofs"},
      {"ZeroAxis",
       [](rigc::RigSpec& s) {
         s.joints[2].dofs[0].axis = {0, 0, 0};
       },
       "joint[2].dof axis"},
      {"MinAboveMax",
       [](rigc::RigSpec& s) {
         s.joints[1].dofs[1].min = 30;
         s.joints[1].dofs[1].max = 10;
       },
       "joint[1].dof limits"},
      {"NineInfluences",
       [](rigc::RigSpec& s) {
         s.vertices[5].influences.clear();
         for (int i = 0; i < 9; ++i) s.vertices[5].influences.push_back({i % 3, 1.0 / 9});
       },
       "vertex[5].influences"},
      {"AllZeroWeights",
       [](rigc::RigSpec& s) {
         for (rigc::Influence& in : s.vertices[3].influences) in.weight = 0;
       },
       "vertex[3].weights"},
      {"NegativeWeight", [](rigc::RigSpec& s) { s.vertices[8].influences[1].weight = -0.25; }, "vertex[8].weight"},
      {"NanPosition", [](rigc::RigSpec& s) { s.vertices[4].position[1] = std::numeric_limits<double>::quiet_NaN(); },
       "vertex[4].position"},
      {"InverseBindEntry100", [](rigc::RigSpec& s) { s.palette[1].inverse_bind[5] = 100; }, "palette[1].inverse_bind"},
      {"PaletteJointMissing", [](rigc::RigSpec& s) { s.palette[2].joint = 3; }, "palette[2].joint"},
      {"InfluenceOfMissingPaletteEntry", [](rigc::RigSpec& s) { s.vertices[9].influences[0].palette = 3; },
       "vertex[9].joint"},
      {"TriangleIndexBeyondVertices", [](rigc::RigSpec& s) { s.triangles[4][2] = 20; }, "triangle[4].index"},
      {"SynergySourceMissing", [](rigc::RigSpec& s) { s.synergies[0].source_input = 4; }, "synergy[0].source_input"},
  };
}

class RigCompileRejects : public ::testing::TestWithParam<BadSpec> {};

TEST_P(RigCompileRejects, WithAMessageNamingTheItem) {
  rigc::RigSpec spec = sample_rig_spec();
  GetParam().edit(spec);
  std::vector<uint8_t> blob;
  rigc::CompileReport report;
  std::string error;
  EXPECT_FALSE(rigc::compile_rig(spec, &blob, &report, &error));
  EXPECT_TRUE(blob.empty());
  EXPECT_NE(error.find(GetParam().where), std::string::npos) << "expected '" << GetParam().where << "' in: " << error;
}

INSTANTIATE_TEST_SUITE_P(Specs, RigCompileRejects, ::testing::ValuesIn(bad_specs()),
                         [](const ::testing::TestParamInfo<BadSpec>& p) { return std::string(p.param.name); });

// Compiles and loads `spec`; returns vertex v's K weights.
std::vector<int32_t> loaded_weights(const rigc::RigSpec& spec, uint32_t v, rigc::CompileReport* report) {
  std::vector<uint8_t> bytes;
  std::string error;
  EXPECT_TRUE(rigc::compile_rig(spec, &bytes, report, &error)) << error;
  const Blob blob(bytes);
  std::vector<uint64_t> arena(blob.size() / 8);
  rig::Rig r;
  const rig::LoadStatus st = rig::rig_init(blob.data(), blob.size(), arena.data(), arena.size() * 8, &r);
  EXPECT_TRUE(st.ok()) << st.message;
  if (!st.ok()) return {};
  const uint32_t k = r.influences_per_vertex;
  const auto w = r.influence_weight.subspan(size_t{v} * k, k);
  return {w.begin(), w.end()};
}

TEST(RigCompile, RenormalisesWeightsToExactlyOne) {
  rigc::RigSpec spec = sample_rig_spec();
  spec.vertices[1].influences = {{0, 0.5}, {1, 0.3}};  // sums to 0.8
  rigc::CompileReport report;
  const std::vector<int32_t> w = loaded_weights(spec, 1, &report);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(report.renormalized_vertices, 1u);  // every other vertex already sums to 1
  EXPECT_EQ(w[0], 671088640);                   // 0.625 * 2^30, exact
  EXPECT_EQ(w[1], 402653184);                   // 0.375 * 2^30, exact
  EXPECT_EQ(w[2], 0);
  EXPECT_EQ(int64_t{w[0]} + w[1] + w[2], fx::kUnitOne);
}

TEST(RigCompile, RoundingResidueGoesToTheLargestWeight) {
  rigc::RigSpec spec = sample_rig_spec();
  spec.vertices[0].influences = {{2, 1.0}, {0, 1.0}, {1, 1.0}};  // thirds: 3 x 357913941 = 2^30 - 1
  rigc::CompileReport report;
  const std::vector<int32_t> w = loaded_weights(spec, 0, &report);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(report.renormalized_vertices, 1u);
  EXPECT_EQ(w[0], 357913942);
  EXPECT_EQ(w[1], 357913941);
  EXPECT_EQ(w[2], 357913941);
  EXPECT_EQ(int64_t{w[0]} + w[1] + w[2], fx::kUnitOne);
}

TEST(RigCompile, ReportMatchesTheBlob) {
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(rigc::compile_rig(sample_rig_spec(), &bytes, &report, &error)) << error;
  const Blob blob(bytes);
  size_t arena_bytes = 0;
  ASSERT_TRUE(rig::rig_validate(blob.data(), blob.size(), &arena_bytes).ok());
  EXPECT_EQ(report.blob_bytes, bytes.size());
  EXPECT_EQ(report.rig_arena_bytes, arena_bytes);
  EXPECT_EQ(report.joints, 3u);
  EXPECT_EQ(report.inputs, 4u);
  EXPECT_EQ(report.vertices, 20u);
  EXPECT_EQ(report.triangles, 18u);
  EXPECT_EQ(report.influences_per_vertex, 3u);
  EXPECT_EQ(report.renormalized_vertices, 0u);
  EXPECT_GT(report.engine_arena_bytes, 0u);
  EXPECT_EQ(blob.header().version_major, rig::kVersionMajorFirst);  // no shared synergies
  EXPECT_EQ(blob.header().total_size, bytes.size());
}

}  // namespace
}  // namespace sinew::test
