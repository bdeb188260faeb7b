// The GLB writer and the clip encoding, parsed back by an independent
// reader: container layout (glTF 2.0 §4.4), 4-byte alignment, accessor
// counts and min/max, the morph targets and the animation's keys.
#include "host_tools/export/glb_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "host_tools/export/clip_glb.hpp"
#include "host_tools/export/rig_clip.hpp"
#include "tests/host_tools/export/glb_parse.hpp"

namespace sinew::test {
namespace {

using gltf_export::SurfaceClip;

// A unit square of two triangles, two joints, and `frames` frames in which
// vertex 2 rises by 0.1 m per frame and the child joint turns about z.
SurfaceClip square_clip(size_t frames) {
  SurfaceClip clip;
  clip.generator = "test";
  clip.rest_position = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  clip.rest_normal = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  clip.triangles = {0, 1, 2, 0, 2, 3};
  clip.joints = {{"root", -1}, {"child", 0}};
  clip.rest_joints.resize(2);
  clip.rest_joints[1].translation[0] = 1;
  for (size_t k = 0; k < frames; ++k) {
    gltf_export::ClipFrame f;
    f.time_s = 0.01 * static_cast<double>(k);
    f.position = clip.rest_position;
    f.position[8] = 0.1f * static_cast<float>(k);
    gltf_export::vertex_normals(f.position, clip.triangles, &f.normal);
    f.joints = clip.rest_joints;
    const double half = 0.05 * static_cast<double>(k);
    f.joints[1].rotation[2] = static_cast<float>(std::sin(half));
    f.joints[1].rotation[3] = static_cast<float>(std::cos(half));
    clip.frames.push_back(f);
  }
  return clip;
}

ParsedGlb encode_and_parse(const SurfaceClip& clip) {
  std::vector<uint8_t> bytes;
  std::string error;
  EXPECT_TRUE(gltf_export::encode_clip_glb(clip, &bytes, &error)) << error;
  ParsedGlb glb;
  const std::string why = parse_glb(bytes, &glb);
  EXPECT_EQ(why, "");
  return glb;
}

TEST(GlbWriter, ContainerHeaderChunksAndAlignment) {
  gltf_export::GlbBuilder builder("test");
  const float three[3] = {1, 2, 3};
  const uint8_t odd[5] = {1, 2, 3, 4, 5};
  builder.add_view(odd, sizeof(odd), 0);
  const int a = builder.add_float_accessor(three, "SCALAR", true, 0);
  const std::vector<uint8_t> bytes = builder.finish();
  ParsedGlb glb;
  ASSERT_EQ(parse_glb(bytes, &glb), "");
  EXPECT_EQ(glb.version, 2u);
  EXPECT_EQ(bytes.size() % 4, 0u);
  EXPECT_EQ(glb.doc["asset"]["version"], "2.0");
  // The second view starts at the next multiple of 4 after the 5 odd bytes.
  EXPECT_EQ(glb.doc["bufferViews"][1]["byteOffset"], 8);
  EXPECT_EQ(glb.doc["buffers"][0]["byteLength"], glb.bin_length);
  EXPECT_EQ(glb.bin_length, 20u);
  EXPECT_EQ(accessor_floats(glb, static_cast<size_t>(a)), std::vector<float>({1, 2, 3}));
  EXPECT_EQ(glb.doc["accessors"][0]["min"], nlohmann::json({1.0}));
  EXPECT_EQ(glb.doc["accessors"][0]["max"], nlohmann::json({3.0}));
  // The JSON chunk is padded with spaces, the gaps between views with zeros.
  const char json_end = static_cast<char>(bytes[20 + glb.json_length - 1]);
  EXPECT_TRUE(json_end == ' ' || json_end == '}') << json_end;
  for (size_t i = 5; i < 8; ++i) EXPECT_EQ(glb.bin[i], 0) << "alignment padding at " << i;
}

TEST(GlbWriter, AWrongElementCountThrows) {
  gltf_export::GlbBuilder builder("test");
  const float four[4] = {1, 2, 3, 4};
  EXPECT_THROW(builder.add_float_accessor(four, "VEC3", false, 0), std::invalid_argument);
}

TEST(GlbWriter, ClipMorphTargetsAndAnimationReadBack) {
  const size_t frames = 5;
  const SurfaceClip clip = square_clip(frames);
  const ParsedGlb glb = encode_and_parse(clip);
  const nlohmann::json& prim = glb.doc["meshes"][0]["primitives"][0];
  const size_t position = prim["attributes"]["POSITION"];
  EXPECT_EQ(glb.doc["accessors"][position]["count"], 4);
  EXPECT_EQ(glb.doc["accessors"][position]["min"], nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(glb.doc["accessors"][position]["max"], nlohmann::json({1.0, 1.0, 0.0}));
  EXPECT_EQ(glb.doc["accessors"][prim["indices"].get<size_t>()]["count"], 6);
  ASSERT_EQ(prim["targets"].size(), frames);
  for (const auto& view : glb.doc["bufferViews"]) EXPECT_EQ(view["byteOffset"].get<size_t>() % 4, 0u);
  // Target k moves vertex 2 by 0.1 k in z; its POSITION accessor's min/max say so.
  for (size_t k = 0; k < frames; ++k) {
    const size_t dp = prim["targets"][k]["POSITION"];
    const std::vector<float> d = accessor_floats(glb, dp);
    ASSERT_EQ(d.size(), 12u);
    EXPECT_FLOAT_EQ(d[8], 0.1f * static_cast<float>(k));
    EXPECT_FLOAT_EQ(glb.doc["accessors"][dp]["max"][2].get<float>(), 0.1f * static_cast<float>(k));
  }
  const nlohmann::json& anim = glb.doc["animations"][0];
  ASSERT_EQ(anim["channels"].size(), 1 + 2 * clip.joints.size());
  EXPECT_EQ(anim["channels"][0]["target"]["path"], "weights");
  const size_t input = anim["samplers"][0]["input"], output = anim["samplers"][0]["output"];
  EXPECT_EQ(glb.doc["accessors"][input]["count"], frames);
  EXPECT_FLOAT_EQ(glb.doc["accessors"][input]["max"][0].get<float>(), 0.04f);
  // One-hot keys: frame k has weight 1 on target k only.
  const std::vector<float> w = accessor_floats(glb, output);
  ASSERT_EQ(w.size(), frames * frames);
  for (size_t k = 0; k < frames; ++k)
    for (size_t t = 0; t < frames; ++t) EXPECT_EQ(w[k * frames + t], k == t ? 1.0f : 0.0f);
  // The child joint is a child node of the root, animated in rotation.
  EXPECT_EQ(glb.doc["nodes"][1]["children"], nlohmann::json({2}));
  EXPECT_EQ(glb.doc["scenes"][0]["nodes"], nlohmann::json({0, 1}));
}

TEST(GlbWriter, BadClipsAreRefusedWithAReason) {
  std::vector<uint8_t> bytes;
  std::string error;
  SurfaceClip clip = square_clip(2);
  clip.triangles[5] = 4;
  EXPECT_FALSE(gltf_export::encode_clip_glb(clip, &bytes, &error));
  EXPECT_NE(error.find("triangle index 4"), std::string::npos) << error;
  clip = square_clip(2);
  clip.frames[1].time_s = 0;
  EXPECT_FALSE(gltf_export::encode_clip_glb(clip, &bytes, &error));
  EXPECT_NE(error.find("increase strictly"), std::string::npos) << error;
  clip = square_clip(0);
  EXPECT_FALSE(gltf_export::encode_clip_glb(clip, &bytes, &error));
  EXPECT_NE(error.find("no frames"), std::string::npos) << error;
}

TEST(GlbWriter, DerivedNormalsAreUnitAndFaceTheTriangles) {
  const std::vector<float> position = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
  const std::vector<uint32_t> triangles = {0, 1, 2};
  std::vector<float> normal;
  gltf_export::vertex_normals(position, triangles, &normal);
  ASSERT_EQ(normal.size(), 12u);
  for (size_t v = 0; v < 3; ++v) EXPECT_EQ(normal[3 * v + 2], 1.0f);
  // A vertex on no triangle still gets a unit normal (glTF requires unit NORMALs).
  EXPECT_EQ(normal[11], 1.0f);
}

}  // namespace
}  // namespace sinew::test
