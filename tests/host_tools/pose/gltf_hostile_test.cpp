// The glTF importer (shared by rigc and sinew-pose) against hostile and
// unusual files, each built here from a small valid skin: it must load what
// real exporters write (images, texture extensions, unnamed nodes) and refuse
// the rest with one message and a non-zero exit, never crash, hang or write
// a silently wrong result.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gltf_oracle.hpp"
#include "host_tools/rigc/gltf_poser.hpp"
#include "synthetic_gltf.hpp"

namespace {

namespace hfs = std::filesystem;
using sinew::oracle::testing::GltfBuilder;
using sinew::oracle::testing::temp_path;

// A triangle skinned to joints 1 and 2 (node 2 a child of node 1), with an
// animation translating node 2. Accessors: 0 POSITION, 1 JOINTS_0,
// 2 WEIGHTS_0, 3 inverse binds, 4 key times, 5 key values.
GltfBuilder hostile_skin(const std::vector<float>& weights = std::vector<float>(12, 0.5f),
                         const std::vector<float>& key_values = {0, 0, 0, 1, 0, 0}) {
  GltfBuilder b;
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  b.add_accessor(b.add_view(pos), 5126, 3, "VEC3", {{"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
  const std::vector<uint16_t> joints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
  b.add_accessor(b.add_view(joints), 5123, 3, "VEC4");
  b.add_accessor(b.add_view(weights), 5126, 3, "VEC4");
  std::vector<float> ibm;
  for (int m = 0; m < 2; ++m) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  b.add_accessor(b.add_view(ibm), 5126, 2, "MAT4");
  b.add_accessor(b.add_view(std::vector<float>{0, 1}), 5126, 2, "SCALAR", {{"min", {0}}, {"max", {1}}});
  b.add_accessor(b.add_view(key_values), 5126, 2, "VEC3");
  b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"JOINTS_0", 1}, {"WEIGHTS_0", 2}}}}}}}};
  b.doc["nodes"] = {
      {{"mesh", 0}, {"skin", 0}}, {{"name", "root"}, {"children", {2}}}, {{"name", "tip"}, {"translation", {1, 0, 0}}}};
  b.doc["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", 3}}};
  b.doc["animations"] = {{{"samplers", {{{"input", 4}, {"output", 5}}}},
                          {"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "translation"}}}}}}}};
  b.doc["scenes"] = {{{"nodes", {0, 1}}}};
  b.doc["scene"] = 0;
  return b;
}

// Opens `path` with the poser; returns the error ("" when it opened).
std::string hostile_open_error(const std::string& path) {
  sinew::rigc::GltfPoser poser;
  std::string error;
  return poser.open(path, &error) ? std::string() : (error.empty() ? std::string("(empty message)") : error);
}

bool hostile_contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Runs a shell command; its exit code, or 128 + signal if it died.
int hostile_run(const std::string& command) {
  const int status = std::system(command.c_str());
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

std::string hostile_slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A .glb as its JSON chunk and BIN chunk, and back.
struct HostileGlb {
  nlohmann::json doc;
  std::string bin;
};

HostileGlb hostile_read_glb(const std::string& path) {
  const std::string bytes = hostile_slurp(path);
  HostileGlb g;
  size_t at = 12;
  while (at + 8 <= bytes.size()) {
    uint32_t length = 0, type = 0;
    std::memcpy(&length, bytes.data() + at, 4);
    std::memcpy(&type, bytes.data() + at + 4, 4);
    const std::string chunk = bytes.substr(at + 8, length);
    if (type == 0x4E4F534Au) g.doc = nlohmann::json::parse(chunk);
    if (type == 0x004E4942u) g.bin = chunk;
    at += 8 + length;
  }
  return g;
}

std::string hostile_write_glb(const HostileGlb& g, const std::string& name) {
  std::string json = g.doc.dump();
  json.resize((json.size() + 3) / 4 * 4, ' ');
  std::string bin = g.bin;
  bin.resize((bin.size() + 3) / 4 * 4, '\0');
  const auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string out = "glTF" + u32(2) + u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  out += u32(static_cast<uint32_t>(json.size())) + u32(0x4E4F534Au) + json;
  out += u32(static_cast<uint32_t>(bin.size())) + u32(0x004E4942u) + bin;
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << out;
  return path;
}

std::vector<std::array<double, 3>> hostile_pose(const std::string& path, int animation, double time) {
  sinew::rigc::GltfPoser poser;
  std::string error;
  std::vector<std::array<double, 3>> out;
  EXPECT_TRUE(poser.open(path, &error)) << path << ": " << error;
  if (error.empty()) EXPECT_TRUE(poser.pose(animation, time, &out, &error)) << path << ": " << error;
  return out;
}

const std::string kHostileData = SINEW_TEST_DATA_DIR;

}  // namespace

// Real files carry textures: images (external, missing, data URIs, in
// bufferViews) and KTX2 / WebP texture extensions are ignored, not refused.
TEST(GltfHostile, ImagesAndTextureExtensionsAreIgnored) {
  GltfBuilder b = hostile_skin();
  const std::string plain = b.write("plain.gltf");
  const int image_view = b.add_raw_view({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A});
  b.doc["images"] = {{{"uri", "missing-texture.png"}},
                     {{"uri", "data:image/png;base64,iVBORw0KGgo="}},
                     {{"bufferView", image_view}, {"mimeType", "image/png"}},
                     {{"uri", "missing.ktx2"}, {"mimeType", "image/ktx2"}},
                     {{"uri", "missing.webp"}, {"mimeType", "image/webp"}}};
  b.doc["textures"] = {{{"source", 0}},
                       {{"source", 2}},
                       {{"extensions", {{"KHR_texture_basisu", {{"source", 3}}}}}},
                       {{"source", 1}, {"extensions", {{"EXT_texture_webp", {{"source", 4}}}}}}};
  b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 2}}}}}}};
  b.doc["meshes"][0]["primitives"][0]["material"] = 0;
  b.doc["extensionsUsed"] = {"KHR_texture_basisu", "EXT_texture_webp"};
  b.doc["extensionsRequired"] = {"KHR_texture_basisu", "EXT_texture_webp"};
  const std::string textured = b.write("textured.gltf");
  const std::string error = hostile_open_error(textured);
  EXPECT_EQ(error, "");
  std::printf("textured .gltf: %s\n", error.empty() ? "loads" : error.c_str());
  EXPECT_EQ(hostile_pose(textured, 0, 0.5), hostile_pose(plain, 0, 0.5));

  // A real .glb with an image in its binary chunk.
  HostileGlb g = hostile_read_glb(kHostileData + "/RiggedSimple.glb");
  ASSERT_FALSE(g.doc.is_null());
  g.doc["images"] = {{{"bufferView", 0}, {"mimeType", "image/png"}}};
  g.doc["textures"] = {{{"source", 0}}};
  const std::string glb = hostile_write_glb(g, "textured.glb");
  EXPECT_EQ(hostile_open_error(glb), "");
  EXPECT_EQ(hostile_pose(glb, 0, 1.0), hostile_pose(kHostileData + "/RiggedSimple.glb", 0, 1.0));

  // Compressed geometry cannot be read: refused rather than read as zeros.
  GltfBuilder draco = hostile_skin();
  draco.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  draco.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  EXPECT_TRUE(hostile_contains(hostile_open_error(draco.write("draco.gltf")), "KHR_draco_mesh_compression"));
}

// Counts, offsets and strides that wrap size_t arithmetic or exceed the
// buffer: refused with a message naming the accessor, nothing allocated.
TEST(GltfHostile, AccessorArithmeticCannotOverflow) {
  struct Case {
    const char* name;
    void (*edit)(nlohmann::json&);
    const char* expect;
  };
  const Case cases[] = {
      // (count - 1) * 12 wraps to -4 and count * 3 to 2: a heap overflow write.
      {"count wraps", [](nlohmann::json& d) { d["accessors"][0]["count"] = uint64_t{6148914691236517206u}; },
       "accessor 0"},
      // byteOffset + 36 wraps to 28: the read started 8 bytes before the view.
      {"accessor byteOffset wraps",
       [](nlohmann::json& d) { d["accessors"][0]["byteOffset"] = std::numeric_limits<uint64_t>::max() - 7; },
       "accessor 0"},
      {"bufferView byteOffset wraps",
       [](nlohmann::json& d) { d["bufferViews"][0]["byteOffset"] = std::numeric_limits<uint64_t>::max() - 15; },
       "exceeds its buffer"},
      // 10^11 VEC3 without a bufferView asked for 2.4 TB of zeros.
      {"huge count without a view",
       [](nlohmann::json& d) {
         d["accessors"][0].erase("bufferView");
         d["accessors"][0]["count"] = uint64_t{100000000000u};
       },
       "exceeds the limit"},
      {"count beyond the view", [](nlohmann::json& d) { d["accessors"][0]["count"] = 4; }, "exceed the bufferView"},
      {"stride smaller than the element", [](nlohmann::json& d) { d["bufferViews"][0]["byteStride"] = 4; },
       "smaller than the element"},
      {"normalized float", [](nlohmann::json& d) { d["accessors"][0]["normalized"] = true; }, "normalized"},
      {"sparse count beyond the accessor",
       [](nlohmann::json& d) {
         d["accessors"][0]["sparse"] = {
             {"count", 5}, {"indices", {{"bufferView", 1}, {"componentType", 5123}}}, {"values", {{"bufferView", 0}}}};
       },
       "sparse"},
      {"sparse negative byteOffset",
       [](nlohmann::json& d) {
         d["accessors"][0]["sparse"] = {{"count", 1},
                                        {"indices", {{"bufferView", 1}, {"componentType", 5123}, {"byteOffset", -8}}},
                                        {"values", {{"bufferView", 0}}}};
       },
       "negative byteOffset"},
      // Index 16256: the high half of the float 1.0 in the inverse binds' view.
      {"sparse index beyond count",
       [](nlohmann::json& d) {
         d["accessors"][0]["sparse"] = {{"count", 1},
                                        {"indices", {{"bufferView", 3}, {"componentType", 5123}, {"byteOffset", 2}}},
                                        {"values", {{"bufferView", 0}}}};
       },
       "index 16256 beyond count"},
  };
  for (const Case& c : cases) {
    GltfBuilder b = hostile_skin();
    c.edit(b.doc);
    const std::string error = hostile_open_error(b.write("accessor.gltf"));
    EXPECT_TRUE(hostile_contains(error, c.expect)) << c.name << ": " << error;
    std::printf("%-32s -> %s\n", c.name, error.c_str());
  }
  // Normalized shorts and sparse substitution still read correctly.
  GltfBuilder b = hostile_skin();
  const std::vector<int16_t> quantised = {0, 0, 0, 32767, 0, 0, 0, 32767, 0};
  b.doc["accessors"][0]["bufferView"] = b.add_view(quantised);
  b.doc["accessors"][0]["componentType"] = 5122;
  b.doc["accessors"][0]["normalized"] = true;
  b.doc["accessors"][0]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", b.add_view(std::vector<uint8_t>{2, 0, 0, 0})}, {"componentType", 5121}}},
      {"values", {{"bufferView", b.add_view(std::vector<int16_t>{0, -32767, 0})}}}};
  sinew::rigc::GltfRig rig;
  std::string error;
  ASSERT_TRUE(sinew::rigc::import_gltf(b.write("normalized.gltf"), &rig, &error)) << error;
  ASSERT_EQ(rig.spec.vertices.size(), 3u);
  EXPECT_EQ(rig.spec.vertices[1].position, (sinew::rigc::Vec3d{1, 0, 0}));
  EXPECT_EQ(rig.spec.vertices[2].position, (sinew::rigc::Vec3d{0, -1, 0}));
}

// Exceptions from tinygltf or the allocator end as one message, never abort.
TEST(GltfHostile, BadFilesAreMessagesNotExceptions) {
  // A .glb buffer of byteLength 0: tinygltf's data.at(0) threw out_of_range.
  HostileGlb g = hostile_read_glb(kHostileData + "/RiggedSimple.glb");
  g.doc["buffers"][0]["byteLength"] = 0;
  const std::string zero = hostile_write_glb(g, "zero_length.glb");
  std::string error;
  EXPECT_NO_THROW(error = hostile_open_error(zero));
  EXPECT_FALSE(error.empty());
  std::printf("byteLength 0: %s\n", error.c_str());
  // A directory: reading it as a file asked for an exabyte.
  const std::string dir = temp_path("a_directory.gltf");
  hfs::create_directory(dir);
  EXPECT_NO_THROW(error = hostile_open_error(dir));
  EXPECT_TRUE(hostile_contains(error, "not a regular file")) << error;
  EXPECT_NO_THROW(error = hostile_open_error(temp_path("does_not_exist.glb")));
  EXPECT_TRUE(hostile_contains(error, "no such file")) << error;
  // The command-line tools: one message, exit code 1, not a crash (134).
  const std::string log = temp_path("bad_files.log");
  for (const std::string& bad : {zero, dir}) {
    EXPECT_EQ(
        hostile_run(std::string(SINEW_POSE_EXE) + " " + bad + " --time 0 --out " + temp_path("x.csv") + " 2>" + log), 1)
        << bad;
    EXPECT_TRUE(hostile_contains(hostile_slurp(log), "sinew-pose: ")) << hostile_slurp(log);
    EXPECT_EQ(hostile_run(std::string(SINEW_RIGC_EXE) + " " + bad + " -o " + temp_path("x.rig") + " 2>" + log), 1)
        << bad;
    EXPECT_TRUE(hostile_contains(hostile_slurp(log), "rigc: ")) << hostile_slurp(log);
  }
  hfs::remove(dir);
}

// Node cycles spun forever in the ancestor walk; deep chains overflowed the
// stack of the recursive visit.
// The in-memory importer (what gltf_import_fuzz drives) is the file
// importer's core: the same bytes give the same rig blob. Without a base
// directory a buffer the document names by file URI is refused, not read.
TEST(GltfHostile, FromMemoryMatchesTheFileAndReadsNoOtherFile) {
  const auto read_bytes = [](const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<uint8_t>{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
  };
  const auto blob = [](const sinew::rigc::GltfRig& rig) {
    std::vector<uint8_t> out;
    sinew::rigc::CompileReport report;
    std::string error;
    EXPECT_TRUE(sinew::rigc::compile_rig(rig.spec, &out, &report, &error)) << error;
    return out;
  };
  for (const std::string name : {"RiggedSimple.glb", "SimpleSkin.gltf"}) {
    SCOPED_TRACE(name);
    const std::string path = kHostileData + "/" + name;
    sinew::rigc::GltfRig from_file, from_memory;
    std::string error;
    ASSERT_TRUE(sinew::rigc::import_gltf(path, &from_file, &error)) << error;
    ASSERT_TRUE(sinew::rigc::import_gltf_from_memory(read_bytes(path), name, "", &from_memory, &error)) << error;
    EXPECT_EQ(from_memory.joint_node, from_file.joint_node);
    EXPECT_EQ(blob(from_memory), blob(from_file));
  }

  // The skin's buffer moved to a file beside the document.
  tinygltf::Model model;
  std::string error;
  ASSERT_TRUE(sinew::rigc::load_gltf_model(hostile_skin().write("embedded.gltf"), &model, &error)) << error;
  const std::string bin = temp_path("external.bin");
  std::ofstream(bin, std::ios::binary)
      .write(reinterpret_cast<const char*>(model.buffers[0].data.data()),
             static_cast<std::streamsize>(model.buffers[0].data.size()));
  GltfBuilder b = hostile_skin();
  nlohmann::json doc = b.doc;
  doc["buffers"] = {{{"byteLength", model.buffers[0].data.size()}, {"uri", hfs::path(bin).filename().string()}}};
  const std::string gltf = temp_path("external.gltf");
  std::ofstream(gltf) << doc.dump();
  const std::vector<uint8_t> bytes = read_bytes(gltf);
  sinew::rigc::GltfRig rig;
  EXPECT_TRUE(sinew::rigc::import_gltf(gltf, &rig, &error)) << error;
  EXPECT_TRUE(sinew::rigc::import_gltf_from_memory(bytes, "external.gltf", hfs::path(gltf).parent_path().string(), &rig,
                                                   &error))
      << error;
  sinew::rigc::GltfRig refused;
  EXPECT_FALSE(sinew::rigc::import_gltf_from_memory(bytes, "external.gltf", "", &refused, &error));
  EXPECT_TRUE(hostile_contains(error, "not read: the document was given as bytes")) << error;
}

TEST(GltfHostile, NodeCyclesAndDeepChainsAreRefusedNamingTheNode) {
  GltfBuilder self = hostile_skin();
  self.doc["nodes"][1]["children"] = {2, 1};
  std::string error = hostile_open_error(self.write("self_child.gltf"));
  EXPECT_TRUE(hostile_contains(error, "node 1")) << error;
  std::printf("self child: %s\n", error.c_str());

  GltfBuilder cycle = hostile_skin();  // 1 -> 2 -> 3 -> 1, no root
  cycle.doc["nodes"][2]["children"] = {3};
  cycle.doc["nodes"].push_back({{"name", "loop"}, {"children", {1}}});
  error = hostile_open_error(cycle.write("cycle.gltf"));
  EXPECT_TRUE(hostile_contains(error, "cycle")) << error;
  EXPECT_TRUE(hostile_contains(error, "node 1")) << error;
  std::printf("cycle: %s\n", error.c_str());

  GltfBuilder deep = hostile_skin();
  const int chain = 100000;
  for (int i = 0; i < chain; ++i) {
    nlohmann::json n = {{"translation", {0, 0.001, 0}}};
    if (i + 1 < chain) n["children"] = {3 + i + 1};
    deep.doc["nodes"].push_back(n);
  }
  deep.doc["nodes"][2]["children"] = {3};
  deep.doc["skins"][0]["joints"] = {1, 2, 3 + chain - 1};
  error = hostile_open_error(deep.write("deep.gltf"));
  EXPECT_TRUE(hostile_contains(error, "levels deep")) << error;
  std::printf("100000 nested nodes: %s\n", error.c_str());

  // 1000 levels is within the limit and imports.
  GltfBuilder ok = hostile_skin();
  for (int i = 0; i < 1000; ++i) {
    nlohmann::json n = {{"translation", {0, 0.001, 0}}};
    if (i + 1 < 1000) n["children"] = {3 + i + 1};
    ok.doc["nodes"].push_back(n);
  }
  ok.doc["nodes"][2]["children"] = {3};
  ok.doc["skins"][0]["joints"] = {1, 2, 3 + 999};
  std::vector<float> ibm;
  for (int m = 0; m < 3; ++m) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  ok.doc["accessors"][3]["bufferView"] = ok.add_view(ibm);
  ok.doc["accessors"][3]["count"] = 3;
  EXPECT_EQ(hostile_open_error(ok.write("deep_ok.gltf")), "");
}

// Non-finite data used to become (0,0,0) or be dropped; now it is refused,
// naming the accessor, node or option.
TEST(GltfHostile, NonFiniteDataIsRefused) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  // An animation sample: every vertex came out at (0,0,0).
  {
    const std::string path = hostile_skin(std::vector<float>(12, 0.5f), {0, 0, 0, nan, 0, 0}).write("nan_key.gltf");
    sinew::rigc::GltfPoser poser;
    std::string error;
    ASSERT_TRUE(poser.open(path, &error)) << error;
    std::vector<std::array<double, 3>> out;
    EXPECT_FALSE(poser.pose(0, 0.5, &out, &error));
    EXPECT_TRUE(hostile_contains(error, "accessor 5")) << error;
    std::printf("NaN key: %s\n", error.c_str());
    // The time itself.
    EXPECT_FALSE(poser.pose(0, std::nan(""), &out, &error));
    EXPECT_TRUE(hostile_contains(error, "not finite")) << error;
  }
  // A weight: silently dropped.
  {
    std::vector<float> w(12, 0.5f);
    w[4] = nan;
    EXPECT_TRUE(hostile_contains(hostile_open_error(hostile_skin(w).write("nan_weight.gltf")), "accessor 2"));
  }
  // An inverse bind translation: silently zero.
  {
    GltfBuilder b = hostile_skin();
    std::vector<float> ibm;
    for (int m = 0; m < 2; ++m) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, inf, 0, 0, 1});
    b.doc["accessors"][3]["bufferView"] = b.add_view(ibm);
    const std::string error = hostile_open_error(b.write("inf_ibm.gltf"));
    EXPECT_TRUE(hostile_contains(error, "accessor 3")) << error;
  }
  // A normal: silently zero.
  {
    GltfBuilder b = hostile_skin();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] =
        b.add_accessor(b.add_view(std::vector<float>{0, 0, 1, 0, 0, 1, nan, 0, 1}), 5126, 3, "VEC3");
    EXPECT_TRUE(hostile_contains(hostile_open_error(b.write("nan_normal.gltf")), "not finite"));
  }
  // A node matrix whose scale overflows to infinity.
  {
    GltfBuilder b = hostile_skin();
    b.doc["nodes"][2].erase("translation");
    b.doc["nodes"][2]["matrix"] = {1e300, 1e300, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const std::string error = hostile_open_error(b.write("inf_matrix.gltf"));
    EXPECT_TRUE(hostile_contains(error, "node 2 (tip)")) << error;
    std::printf("node matrix 1e300: %s\n", error.c_str());
  }
  // A translation with two numbers was ignored.
  {
    GltfBuilder b = hostile_skin();
    b.doc["nodes"][2]["translation"] = {1, 0};
    const std::string error = hostile_open_error(b.write("short_translation.gltf"));
    EXPECT_TRUE(hostile_contains(error, "node 2 (tip)")) << error;
  }
  // --time nan on the command line.
  const std::string out = temp_path("nan_time.csv");
  EXPECT_EQ(hostile_run(std::string(SINEW_POSE_EXE) + " " + hostile_skin().write("time.gltf") + " --time nan --out " +
                        out + " 2>/dev/null"),
            1);
  EXPECT_FALSE(hfs::exists(out));
}

// A negative weight was dropped silently; now the primitive is named.
TEST(GltfHostile, NegativeWeightsAreRefusedNamingThePrimitive) {
  std::vector<float> w(12, 0.5f);
  w[5] = -0.25f;
  const std::string error = hostile_open_error(hostile_skin(w).write("negative_weight.gltf"));
  EXPECT_TRUE(hostile_contains(error, "node 0 primitive 0")) << error;
  EXPECT_TRUE(hostile_contains(error, "negative weight")) << error;
  std::printf("negative weight: %s\n", error.c_str());
}

// A coordinate of 1e30 clamps the rig unit: positions saturate, so say so.
TEST(GltfHostile, ClampedRigUnitIsWarnedAbout) {
  GltfBuilder b = hostile_skin();
  b.doc["accessors"][0]["bufferView"] = b.add_view(std::vector<float>{0, 0, 0, 1e30f, 0, 0, 0, 1, 0});
  const std::string path = b.write("huge.gltf");
  const std::string log = temp_path("huge.log");
  EXPECT_EQ(
      hostile_run(std::string(SINEW_POSE_EXE) + " " + path + " --time 0 --out " + temp_path("huge.csv") + " 2>" + log),
      0);
  EXPECT_TRUE(hostile_contains(hostile_slurp(log), "clamped")) << hostile_slurp(log);
  EXPECT_EQ(hostile_run(std::string(SINEW_RIGC_EXE) + " " + path + " >/dev/null 2>" + log), 0);
  EXPECT_TRUE(hostile_contains(hostile_slurp(log), "clamped")) << hostile_slurp(log);
  // The real assets are not clamped.
  EXPECT_EQ(hostile_run(std::string(SINEW_RIGC_EXE) + " " + kHostileData + "/RiggedSimple.glb >/dev/null 2>" + log), 0);
  EXPECT_EQ(hostile_slurp(log), "");
}

// Writing to a full disk exited 0.
TEST(GltfHostile, FullDiskIsAnError) {
  if (!hfs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string model = kHostileData + "/SimpleSkin.gltf";
  EXPECT_EQ(hostile_run(std::string(SINEW_POSE_EXE) + " " + model + " --time 0.5 --out /dev/full 2>/dev/null"), 1);
  EXPECT_EQ(hostile_run(std::string(SINEW_RIGC_EXE) + " " + model + " -o /dev/full >/dev/null 2>/dev/null"), 1);
  EXPECT_EQ(hostile_run(std::string(SINEW_RIGC_EXE) + " " + model + " >/dev/full 2>/dev/null"), 1);
}

// No animation: --bind-pose writes the bind pose; without it nothing is
// written (it used to leave a two-line CSV behind the error).
TEST(GltfHostile, BindPoseAndNoPartialOutput) {
  const std::string model = kHostileData + "/generic-hand_left.glb";
  const std::string partial = temp_path("no_animation.csv");
  EXPECT_EQ(hostile_run(std::string(SINEW_POSE_EXE) + " " + model + " --time 0 --out " + partial + " 2>/dev/null"), 1);
  EXPECT_FALSE(hfs::exists(partial));

  const std::string out = temp_path("bind.csv");
  ASSERT_EQ(hostile_run(std::string(SINEW_POSE_EXE) + " " + model + " --bind-pose --out " + out), 0);
  std::ifstream csv(out);
  std::string line;
  std::vector<std::array<double, 3>> rows;
  while (std::getline(csv, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::array<double, 3> p{};
    char c1 = 0, c2 = 0;
    std::istringstream(line) >> p[0] >> c1 >> p[1] >> c2 >> p[2];
    rows.push_back(p);
  }
  sinew::oracle::OracleResult ref;
  std::string error;
  ASSERT_TRUE(sinew::oracle::skinned_pose(model, -1, 0.0, &ref, &error)) << error;
  ASSERT_EQ(rows.size(), ref.positions.size());
  double worst = 0;
  for (size_t v = 0; v < rows.size(); ++v)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(rows[v][static_cast<size_t>(c)] - ref.positions[v][c]));
  std::printf("bind pose: %zu vertices, max error %.3g of the diagonal\n", rows.size(), worst / ref.bbox_diagonal);
  EXPECT_LE(worst / ref.bbox_diagonal, 2e-5);
}

// Nodes without names (RiggedFigure has none) get stable, unique names.
TEST(GltfHostile, UnnamedNodesGetStableUniqueNames) {
  GltfBuilder b = hostile_skin();
  b.doc["nodes"][1].erase("name");
  b.doc["nodes"][2].erase("name");
  b.doc["nodes"][1]["children"] = {2, 3, 4};
  b.doc["nodes"].push_back({{"name", "node2"}});  // 3: takes the name node 2 would get
  b.doc["nodes"].push_back({{"name", "node2"}});  // 4: a duplicate name
  b.doc["skins"][0]["joints"] = {1, 2, 3, 4};
  std::vector<float> ibm;
  for (int m = 0; m < 4; ++m) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  b.doc["accessors"][3]["bufferView"] = b.add_view(ibm);
  b.doc["accessors"][3]["count"] = 4;
  const std::string path = b.write("unnamed.gltf");
  std::vector<std::string> names;
  for (int round = 0; round < 2; ++round) {
    sinew::rigc::GltfRig rig;
    std::string error;
    ASSERT_TRUE(sinew::rigc::import_gltf(path, &rig, &error)) << error;
    std::vector<std::string> got;
    for (const auto& j : rig.spec.joints) got.push_back(j.name);
    if (round == 1) EXPECT_EQ(got, names);  // stable
    names = got;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"node1", "node2~2", "node2", "node2~4"}));
  // The compiled rig carries them.
  sinew::rigc::GltfPoser poser;
  std::string error;
  ASSERT_TRUE(poser.open(path, &error)) << error;
  EXPECT_EQ(poser.report().joints, 4u);

  sinew::rigc::GltfRig figure;
  ASSERT_TRUE(sinew::rigc::import_gltf(kHostileData + "/RiggedFigure.glb", &figure, &error)) << error;
  for (size_t j = 0; j < figure.spec.joints.size(); ++j)
    EXPECT_EQ(figure.spec.joints[j].name, "node" + std::to_string(figure.joint_node[j]));
}
