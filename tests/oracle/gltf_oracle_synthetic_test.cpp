// The oracle on small generated files, one glTF feature at a time, each with
// positions derived by hand from the rig below.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>

#include "gltf_oracle.hpp"
#include "synthetic_gltf.hpp"

namespace sinew::oracle {
namespace {

using testing::GltfBuilder;
using Json = nlohmann::json;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kFloat = 5126;
const double kHalfSqrt2 = std::sqrt(0.5);

// Two-joint rig. Node 0 holds the mesh and skin (translation (100,0,0), which
// skinning must ignore); joint A = node 1 (origin) has child joint B = node 2
// at (0,1,0). Inverse binds: identity and translate(0,-1,0), so the rest pose
// is the bind pose. Vertices: v0 (1,0,0) on A, v1 (1,1,0) on B, v2 (1,2,0)
// half A half B; normals (1,0,0), (0.6,0.8,0), (1,0,0), interleaved with the
// positions (byteStride 24).
struct Rig {
  GltfBuilder gltf;
  Json& attributes() { return gltf.doc["meshes"][0]["primitives"][0]["attributes"]; }
  std::string write(const std::string& name) const { return gltf.write(name); }
};

Rig two_joint_rig() {
  Rig rig;
  GltfBuilder& g = rig.gltf;
  const int interleaved = g.add_view(std::vector<float>{1, 0, 0, 1, 0, 0,        //
                                                        1, 1, 0, 0.6f, 0.8f, 0,  //
                                                        1, 2, 0, 1, 0, 0},
                                     24);
  const int positions = g.add_accessor(interleaved, kFloat, 3, "VEC3");
  const int normals = g.add_accessor(interleaved, kFloat, 3, "VEC3", {{"byteOffset", 12}});
  const int joints =
      g.add_accessor(g.add_view(std::vector<uint8_t>{0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}), kUByte, 3, "VEC4");
  const int weights =
      g.add_accessor(g.add_view(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0}), kFloat, 3, "VEC4");
  const int inverse_binds =
      g.add_accessor(g.add_view(std::vector<float>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1,  //
                                                   1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1}),
                     kFloat, 2, "MAT4");
  g.doc["scenes"] = Json::array({{{"nodes", {0, 1}}}});
  g.doc["nodes"] = Json::array(
      {{{"mesh", 0}, {"skin", 0}, {"translation", {100, 0, 0}}}, {{"children", {2}}}, {{"translation", {0, 1, 0}}}});
  const Json attributes = {{"POSITION", positions}, {"NORMAL", normals}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}};
  g.doc["meshes"] = Json::array({{{"primitives", Json::array({{{"attributes", attributes}}})}}});
  g.doc["skins"] = Json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", inverse_binds}}});
  return rig;
}

// Adds an animation with one channel; `output` is an accessor index.
void animate(Rig* rig, int node, const std::string& path, const std::string& interpolation,
             const std::vector<float>& times, int output) {
  GltfBuilder& g = rig->gltf;
  const int input = g.add_accessor(g.add_view(times), kFloat, times.size(), "SCALAR");
  const Json sampler = {{"input", input}, {"output", output}, {"interpolation", interpolation}};
  const Json channel = {{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}};
  const Json animation = {{"samplers", Json::array({sampler})}, {"channels", Json::array({channel})}};
  if (!g.doc.contains("animations")) g.doc["animations"] = Json::array();
  g.doc["animations"].push_back(animation);
}

int float_output(Rig* rig, const std::vector<float>& values, const std::string& type) {
  const size_t per = type == "VEC4" ? 4 : 3;
  return rig->gltf.add_accessor(rig->gltf.add_view(values), kFloat, values.size() / per, type);
}

OracleResult pose(const std::string& path, int animation, double time) {
  OracleResult result;
  std::string error;
  EXPECT_TRUE(skinned_pose(path, animation, time, &result, &error)) << error;
  return result;
}

std::string pose_error(const std::string& path, int animation = -1, double time = 0) {
  OracleResult result;
  std::string error;
  EXPECT_FALSE(skinned_pose(path, animation, time, &result, &error));
  EXPECT_FALSE(error.empty());
  return error;
}

void expect_positions(const OracleResult& result, const std::vector<Eigen::Vector3d>& expected) {
  ASSERT_EQ(result.positions.size(), expected.size());
  for (size_t v = 0; v < expected.size(); ++v)
    EXPECT_LT((result.positions[v] - expected[v]).norm(), 1e-6)
        << "vertex " << v << ": got (" << result.positions[v].transpose() << "), expected (" << expected[v].transpose()
        << ")";
}

// B rotated by `angle` about +Z maps v1 to (cos, 1 + sin, 0) and v2's B part to
// (cos - sin, 1 + sin + cos, 0).
std::vector<Eigen::Vector3d> rotated_b(double angle, double weight_b2 = 0.5) {
  const double c = std::cos(angle), s = std::sin(angle);
  const Eigen::Vector3d v2_b(c - s, 1 + s + c, 0);
  return {{1, 0, 0}, {c, 1 + s, 0}, (1 - weight_b2) * Eigen::Vector3d(1, 2, 0) + weight_b2 * v2_b};
}

TEST(GltfOracleSynthetic, RestPoseIsTheBindPoseAndIgnoresTheMeshNodeTransform) {
  const OracleResult rest = pose(two_joint_rig().write("rest.gltf"), -1, 0);
  expect_positions(rest, {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
  EXPECT_DOUBLE_EQ(rest.bbox_diagonal, 2.0);
  ASSERT_EQ(rest.normals.size(), 3u);
  EXPECT_LT((rest.normals[1] - Eigen::Vector3d(0.6, 0.8, 0)).norm(), 1e-7);
  EXPECT_EQ(rest.renormalized_vertices, 0);
}

TEST(GltfOracleSynthetic, LinearTranslationInterpolatesAndClamps) {
  Rig rig = two_joint_rig();
  animate(&rig, 1, "translation", "LINEAR", {0, 2}, float_output(&rig, {0, 0, 0, 4, 0, 0}, "VEC3"));
  const std::string path = rig.write("linear.gltf");
  expect_positions(pose(path, 0, 0.5), {{2, 0, 0}, {2, 1, 0}, {2, 2, 0}});
  expect_positions(pose(path, 0, 7.0), {{5, 0, 0}, {5, 1, 0}, {5, 2, 0}});
  expect_positions(pose(path, 0, -1.0), {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
  EXPECT_DOUBLE_EQ(pose(path, 0, 0.5).bbox_diagonal, 2.0);  // rest pose, not the animated one
}

TEST(GltfOracleSynthetic, CubicSplineScalesTangentsByTheKeyframeDelta) {
  // Keys at 0 s and 2 s: values 0 and (1,0,0), out-tangent of key 0 (2,0,0).
  // At u = 0.5: h10 * dt * b0 + h01 * v1 = 0.125 * 2 * 2 + 0.5 * 1 = 1.
  Rig rig = two_joint_rig();
  animate(&rig, 1, "translation", "CUBICSPLINE", {0, 2},
          float_output(&rig, {0, 0, 0, 0, 0, 0, 2, 0, 0, /**/ 0, 0, 0, 1, 0, 0, 0, 0, 0}, "VEC3"));
  expect_positions(pose(rig.write("cubic.gltf"), 0, 1.0), {{2, 0, 0}, {2, 1, 0}, {2, 2, 0}});
}

TEST(GltfOracleSynthetic, CubicSplineRotationIsNormalised) {
  // Zero tangents, identity to 90 degrees about Z: the midpoint is the plain
  // average (0, 0, s/2, (1 + c)/2) of the two, which normalises to 45 degrees.
  Rig rig = two_joint_rig();
  const auto h = static_cast<float>(kHalfSqrt2);
  animate(&rig, 2, "rotation", "CUBICSPLINE", {0, 1},
          float_output(&rig, {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, /**/ 0, 0, 0, 0, 0, 0, h, h, 0, 0, 0, 0}, "VEC4"));
  expect_positions(pose(rig.write("cubic_rotation.gltf"), 0, 0.5), rotated_b(std::numbers::pi / 4));
}

TEST(GltfOracleSynthetic, StepHoldsEachValueUntilTheNextKey) {
  Rig rig = two_joint_rig();
  animate(&rig, 2, "scale", "STEP", {0, 1}, float_output(&rig, {1, 1, 1, 2, 1, 1}, "VEC3"));
  const std::string path = rig.write("step.gltf");
  expect_positions(pose(path, 0, 0.999), {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
  const OracleResult scaled = pose(path, 0, 1.0);
  expect_positions(scaled, {{1, 0, 0}, {2, 1, 0}, {1.5, 2, 0}});
  // Normals take the inverse transpose: (0.6, 0.8, 0) under scale (2,1,1) -> (0.3, 0.8, 0), normalised.
  ASSERT_EQ(scaled.normals.size(), 3u);
  EXPECT_LT((scaled.normals[1] - Eigen::Vector3d(0.3, 0.8, 0).normalized()).norm(), 1e-7);
}

TEST(GltfOracleSynthetic, SlerpTakesTheShorterArc) {
  // The second key is -q for q = 90 degrees about Z: the same rotation, so the
  // midpoint must be 45 degrees, not the long way round.
  Rig rig = two_joint_rig();
  const auto h = static_cast<float>(kHalfSqrt2);
  animate(&rig, 2, "rotation", "LINEAR", {0, 1}, float_output(&rig, {0, 0, 0, 1, 0, 0, -h, -h}, "VEC4"));
  expect_positions(pose(rig.write("shorter_arc.gltf"), 0, 0.5), rotated_b(std::numbers::pi / 4));
}

TEST(GltfOracleSynthetic, QuantisedJointsWeightsAndRotations) {
  // JOINTS_0 as unsigned short, WEIGHTS_0 as normalised unsigned byte (v2:
  // 51/255 = 0.2 on A, 204/255 = 0.8 on B), the rotation as normalised short
  // (0, 0, 23170, 23170) = 90 degrees about Z once normalised.
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["JOINTS_0"] =
      g.add_accessor(g.add_view(std::vector<uint16_t>{0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}), kUShort, 3, "VEC4");
  rig.attributes()["WEIGHTS_0"] =
      g.add_accessor(g.add_view(std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 51, 204, 0, 0}), kUByte, 3, "VEC4",
                     {{"normalized", true}});
  const int rotation =
      g.add_accessor(g.add_view(std::vector<int16_t>{0, 0, 23170, 23170}), kShort, 1, "VEC4", {{"normalized", true}});
  animate(&rig, 2, "rotation", "LINEAR", {0}, rotation);
  const OracleResult result = pose(rig.write("quantised.gltf"), 0, 3.0);
  expect_positions(result, rotated_b(std::numbers::pi / 2, 0.8));
  EXPECT_EQ(result.renormalized_vertices, 0);
}

TEST(GltfOracleSynthetic, NormalisedByteRotationsAndPositions) {
  // POSITION as normalised signed bytes (KHR_mesh_quantization): 127 -> 1.
  // The rotation (0, 0, -127, 127) / 127 is -90 degrees about Z.
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["POSITION"] =
      g.add_accessor(g.add_view(std::vector<int8_t>{127, 0, 0, 0, 127, 127, 0, 0, 127, -128, 0, 0}, 4), kByte, 3,
                     "VEC3", {{"normalized", true}});
  const int rotation =
      g.add_accessor(g.add_view(std::vector<int8_t>{0, 0, -127, 127}), kByte, 1, "VEC4", {{"normalized", true}});
  animate(&rig, 2, "rotation", "STEP", {0}, rotation);
  // v2 is now (1, -1, 0): A leaves it, B maps it to Rz(-90) (1, -2, 0) + (0, 1, 0) = (-2, 0, 0).
  expect_positions(pose(rig.write("byte_positions.gltf"), 0, 0),
                   {{1, 0, 0}, {0, 0, 0}, 0.5 * Eigen::Vector3d(1, -1, 0) + 0.5 * Eigen::Vector3d(-2, 0, 0)});
}

TEST(GltfOracleSynthetic, SparseAccessorsSubstituteValues) {
  // POSITION: v1 replaced by (3,1,0) through sparse. The translation output has
  // no bufferView (zeros) and a sparse (4,0,0) for its second key.
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  const int indices = g.add_view(std::vector<uint8_t>{1});
  const int values = g.add_view(std::vector<float>{3, 1, 0});
  const Json sparse = {{"count", 1},
                       {"indices", {{"bufferView", indices}, {"componentType", kUByte}}},
                       {"values", {{"bufferView", values}}}};
  rig.attributes()["POSITION"] = g.add_accessor(0, kFloat, 3, "VEC3", {{"sparse", sparse}});
  const int key_indices = g.add_view(std::vector<uint16_t>{1});
  const int key_values = g.add_view(std::vector<float>{4, 0, 0});
  const Json key_sparse = {{"count", 1},
                           {"indices", {{"bufferView", key_indices}, {"componentType", kUShort}}},
                           {"values", {{"bufferView", key_values}}}};
  animate(&rig, 1, "translation", "LINEAR", {0, 2}, g.add_accessor(-1, kFloat, 2, "VEC3", {{"sparse", key_sparse}}));
  const std::string path = rig.write("sparse.gltf");
  expect_positions(pose(path, -1, 0), {{1, 0, 0}, {3, 1, 0}, {1, 2, 0}});
  expect_positions(pose(path, 0, 0.5), {{2, 0, 0}, {4, 1, 0}, {2, 2, 0}});
}

TEST(GltfOracleSynthetic, SecondJointAndWeightSet) {
  // v2 carries A in JOINTS_0/WEIGHTS_0 and B in JOINTS_1/WEIGHTS_1.
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["WEIGHTS_0"] =
      g.add_accessor(g.add_view(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0, 0, 0}), kFloat, 3, "VEC4");
  rig.attributes()["JOINTS_1"] =
      g.add_accessor(g.add_view(std::vector<uint8_t>{0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0}), kUByte, 3, "VEC4");
  rig.attributes()["WEIGHTS_1"] = g.add_accessor(g.add_view(std::vector<float>(12, 0.0f)), kFloat, 3, "VEC4");
  rig.gltf.doc["accessors"].back()["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", g.add_view(std::vector<uint8_t>{2})}, {"componentType", kUByte}}},
      {"values", {{"bufferView", g.add_view(std::vector<float>{0.5f, 0, 0, 0})}}}};
  const auto h = static_cast<float>(kHalfSqrt2);
  animate(&rig, 2, "rotation", "LINEAR", {0}, float_output(&rig, {0, 0, h, h}, "VEC4"));
  const OracleResult result = pose(rig.write("two_sets.gltf"), 0, 0);
  expect_positions(result, rotated_b(std::numbers::pi / 2));
  EXPECT_EQ(result.renormalized_vertices, 0);
}

TEST(GltfOracleSynthetic, MissingInverseBindMatricesMeanIdentity) {
  // Then B's skinning matrix is its world transform, translate(0,1,0).
  Rig rig = two_joint_rig();
  rig.gltf.doc["skins"][0].erase("inverseBindMatrices");
  expect_positions(pose(rig.write("no_ibm.gltf"), -1, 0), {{1, 0, 0}, {1, 2, 0}, {1, 2.5, 0}});
}

TEST(GltfOracleSynthetic, MatrixNodesComposeThroughTheParentChain) {
  // A new root (node 3, matrix = translate(10,0,0)) above joint A moves everything.
  Rig rig = two_joint_rig();
  rig.gltf.doc["nodes"].push_back({{"children", {1}}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}});
  rig.gltf.doc["scenes"][0]["nodes"] = {0, 3};
  expect_positions(pose(rig.write("matrix_root.gltf"), -1, 0), {{11, 0, 0}, {11, 1, 0}, {11, 2, 0}});

  animate(&rig, 3, "translation", "LINEAR", {0}, float_output(&rig, {0, 0, 0}, "VEC3"));
  EXPECT_NE(pose_error(rig.write("matrix_animated.gltf"), 0).find("has a matrix"), std::string::npos);
}

TEST(GltfOracleSynthetic, WeightsNotSummingToOneAreRenormalisedAndCounted) {
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["WEIGHTS_0"] =
      g.add_accessor(g.add_view(std::vector<float>{0.25f, 0, 0, 0, 1, 0, 0, 0, 0.2f, 0.2f, 0, 0}), kFloat, 3, "VEC4");
  const OracleResult result = pose(rig.write("unnormalised.gltf"), -1, 0);
  expect_positions(result, {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
  EXPECT_EQ(result.renormalized_vertices, 2);
}

TEST(GltfOracleSynthetic, MorphWeightChannelsAreIgnored) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["nodes"][0]["weights"] = {0.0};
  animate(&rig, 0, "weights", "LINEAR", {0, 1},
          rig.gltf.add_accessor(rig.gltf.add_view(std::vector<float>{0, 1}), kFloat, 2, "SCALAR"));
  expect_positions(pose(rig.write("morph_channel.gltf"), 0, 0.5), {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
}

// --- errors ---------------------------------------------------------------

TEST(GltfOracleSyntheticErrors, JointIndexOutOfRange) {
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["JOINTS_0"] =
      g.add_accessor(g.add_view(std::vector<uint8_t>{5, 0, 0, 0, 1, 9, 0, 0, 0, 1, 0, 0}), kUByte, 3, "VEC4");
  const std::string error = pose_error(rig.write("joint_oob.gltf"));
  EXPECT_NE(error.find("vertex 0 uses joint index 5"), std::string::npos) << error;
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, ZeroWeightSlotsMayNameAnyJoint) {
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["JOINTS_0"] =
      g.add_accessor(g.add_view(std::vector<uint8_t>{0, 200, 0, 0, 1, 9, 0, 0, 0, 1, 77, 0}), kUByte, 3, "VEC4");
  expect_positions(pose(rig.write("zero_weight_oob.gltf"), -1, 0), {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
}

TEST(GltfOracleSyntheticErrors, AllWeightsZero) {
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  rig.attributes()["WEIGHTS_0"] =
      g.add_accessor(g.add_view(std::vector<float>{1, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0.5f, 0, 0}), kFloat, 3, "VEC4");
  const std::string error = pose_error(rig.write("zero_weights.gltf"));
  EXPECT_NE(error.find("vertex 1 has all weights zero"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, FewerInverseBindMatricesThanJoints) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["accessors"][rig.gltf.doc["skins"][0]["inverseBindMatrices"].get<size_t>()]["count"] = 1;
  const std::string error = pose_error(rig.write("short_ibm.gltf"));
  EXPECT_NE(error.find("1 inverse bind matrices for 2 joints"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, AccessorBeyondItsBufferView) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["accessors"][rig.attributes()["POSITION"].get<size_t>()]["count"] = 4;
  const std::string error = pose_error(rig.write("accessor_oob.gltf"));
  EXPECT_NE(error.find("run past"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, ByteStrideSmallerThanTheElement) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["bufferViews"][0]["byteStride"] = 8;
  const std::string error = pose_error(rig.write("small_stride.gltf"));
  EXPECT_NE(error.find("byteStride"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, SparseIndexOutOfRange) {
  Rig rig = two_joint_rig();
  GltfBuilder& g = rig.gltf;
  const Json sparse = {{"count", 1},
                       {"indices", {{"bufferView", g.add_view(std::vector<uint8_t>{3})}, {"componentType", kUByte}}},
                       {"values", {{"bufferView", g.add_view(std::vector<float>{3, 1, 0})}}}};
  rig.attributes()["POSITION"] = g.add_accessor(0, kFloat, 3, "VEC3", {{"sparse", sparse}});
  const std::string error = pose_error(rig.write("sparse_oob.gltf"));
  EXPECT_NE(error.find("sparse index 3 is out of range"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, NoSkinnedMesh) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["nodes"][0].erase("skin");
  const std::string error = pose_error(rig.write("unskinned.gltf"));
  EXPECT_NE(error.find("no skinned mesh"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, NodeCycle) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["nodes"][2]["children"] = {1};
  const std::string error = pose_error(rig.write("cycle.gltf"));
  EXPECT_NE(error.find("cycle"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, RequiredCompressionExtension) {
  Rig rig = two_joint_rig();
  rig.gltf.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  rig.gltf.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  const std::string error = pose_error(rig.write("draco.gltf"));
  EXPECT_NE(error.find("KHR_draco_mesh_compression"), std::string::npos) << error;
}

TEST(GltfOracleSyntheticErrors, MalformedJson) {
  const std::string path = testing::temp_path("malformed.gltf");
  std::ofstream(path) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
  const std::string error = pose_error(path);
  EXPECT_NE(error.find("not a readable glTF"), std::string::npos) << error;
}

}  // namespace
}  // namespace sinew::oracle
