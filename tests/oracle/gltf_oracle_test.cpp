// The oracle on the real third-party assets in tests/data (see ATTRIBUTION.md):
// hand-derived positions for SimpleSkin, sanity of every animation of every
// asset, the RiggedFigure weight quirk, and truncated files.
#include "gltf_oracle.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <numbers>

#include "synthetic_gltf.hpp"

namespace sinew::oracle {
namespace {

std::string data_file(const std::string& name) { return std::string(SINEW_TEST_DATA_DIR) + "/" + name; }

OracleResult pose_or_fail(const std::string& path, int animation, double time) {
  OracleResult result;
  std::string error;
  EXPECT_TRUE(skinned_pose(path, animation, time, &result, &error)) << error;
  return result;
}

void expect_near(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tolerance, int vertex) {
  EXPECT_NEAR((actual - expected).norm(), 0.0, tolerance)
      << "vertex " << vertex << ": got (" << actual.transpose() << "), expected (" << expected.transpose() << ")";
}

// SimpleSkin.gltf, from its JSON: vertices (0|1, 0.5*k, 0) for k = 0..4, i.e.
// vertex 2k = (0, k/2, 0) and 2k+1 = (1, k/2, 0), weights (1 - k/4) on joint 0
// and k/4 on joint 1. Joint 0 is node 1 (translation (0,1,0), under the
// identity mesh node 0); joint 1 is node 2 (its child, rotation only). Both
// inverse bind matrices are translate(-0.5, -1, 0), so at rest both joints
// map v to v + (-0.5, 0, 0). The one animation rotates node 2 about +Z.
std::vector<Eigen::Vector3d> simple_skin_vertices() {
  std::vector<Eigen::Vector3d> v;
  for (int k = 0; k <= 4; ++k) {
    v.emplace_back(0.0, 0.5 * k, 0.0);
    v.emplace_back(1.0, 0.5 * k, 0.0);
  }
  return v;
}

// Expected SimpleSkin position when joint 1 is rotated by `angle` about +Z:
// joint 0 gives v + (-0.5, 0, 0); joint 1 gives T(0,1,0) Rz T(-0.5,-1,0) v.
Eigen::Vector3d simple_skin_expected(int vertex, double angle) {
  const Eigen::Vector3d v = simple_skin_vertices()[static_cast<size_t>(vertex)];
  const double w1 = (vertex / 2) / 4.0;
  const Eigen::Vector3d by_joint0 = v + Eigen::Vector3d(-0.5, 0, 0);
  const Eigen::Vector3d local = v + Eigen::Vector3d(-0.5, -1, 0);
  const Eigen::Vector3d rotated(std::cos(angle) * local.x() - std::sin(angle) * local.y(),
                                std::sin(angle) * local.x() + std::cos(angle) * local.y(), 0.0);
  const Eigen::Vector3d by_joint1 = rotated + Eigen::Vector3d(0, 1, 0);
  return (1.0 - w1) * by_joint0 + w1 * by_joint1;
}

TEST(GltfOracleSimpleSkin, RestAndTimeZeroShiftEveryVertexByMinusHalfX) {
  const std::string path = data_file("SimpleSkin.gltf");
  for (int animation : {-1, 0}) {
    const OracleResult result = pose_or_fail(path, animation, 0.0);
    ASSERT_EQ(result.positions.size(), 10u);
    for (int v = 0; v < 10; ++v)
      expect_near(result.positions[static_cast<size_t>(v)], simple_skin_expected(v, 0), 1e-12, v);
    EXPECT_TRUE(result.normals.empty());  // the file has no NORMAL
    EXPECT_EQ(result.renormalized_vertices, 0);
    EXPECT_NEAR(result.bbox_diagonal, std::sqrt(5.0), 1e-12);  // 1 x 2 rectangle
  }
}

TEST(GltfOracleSimpleSkin, KeyframeAtOneSecondRotatesJointOneByNinetyDegrees) {
  // Key 2 (t = 1.0 s) is (0, 0, 0.707, 0.707): 90 degrees about +Z once normalised.
  const OracleResult result = pose_or_fail(data_file("SimpleSkin.gltf"), 0, 1.0);
  ASSERT_EQ(result.positions.size(), 10u);
  // Worked by hand: vertex 4 (0,1,0), weights 0.5/0.5 -> 0.5*(-0.5,1,0) + 0.5*(0,0.5,0).
  expect_near(result.positions[4], Eigen::Vector3d(-0.25, 0.75, 0), 1e-12, 4);
  expect_near(result.positions[8], Eigen::Vector3d(-1.0, 0.5, 0), 1e-12, 8);
  expect_near(result.positions[9], Eigen::Vector3d(-1.0, 1.5, 0), 1e-12, 9);
  expect_near(result.positions[0], Eigen::Vector3d(-0.5, 0.0, 0), 1e-12, 0);
  for (int v = 0; v < 10; ++v)
    expect_near(result.positions[static_cast<size_t>(v)], simple_skin_expected(v, std::numbers::pi / 2), 1e-12, v);
}

TEST(GltfOracleSimpleSkin, BetweenKeyframesSlerpsTheHalfAngles) {
  // t = 0.75 s is halfway between keys (0,0,0.383,0.924) and (0,0,0.707,0.707):
  // slerp halves the sum of the two half-angles, so the rotation angle is
  // atan2(0.383, 0.924) + atan2(0.707, 0.707) (float32 data, as stored).
  const double angle = std::atan2(double{0.383f}, double{0.924f}) + std::atan2(double{0.707f}, double{0.707f});
  const OracleResult result = pose_or_fail(data_file("SimpleSkin.gltf"), 0, 0.75);
  ASSERT_EQ(result.positions.size(), 10u);
  for (int v = 0; v < 10; ++v)
    expect_near(result.positions[static_cast<size_t>(v)], simple_skin_expected(v, angle), 1e-12, v);
}

TEST(GltfOracleSimpleSkin, MidAnimationAndClampedTimes) {
  const std::string path = data_file("SimpleSkin.gltf");
  double start = -1, end = -1;
  std::string error;
  ASSERT_TRUE(animation_time_range(path, 0, &start, &end, &error)) << error;
  EXPECT_EQ(start, 0.0);
  EXPECT_EQ(end, 5.5);
  // 2.75 s lies between two identity keys (2.5 s and 3.0 s): the rest shape.
  // 3.75 s is halfway between (0,0,-0.383,0.924) and (0,0,-0.707,0.707).
  const OracleResult mid = pose_or_fail(path, 0, 0.5 * (start + end));
  const OracleResult later = pose_or_fail(path, 0, 3.75);
  const double angle = -(std::atan2(double{0.383f}, double{0.924f}) + std::atan2(double{0.707f}, double{0.707f}));
  const OracleResult before = pose_or_fail(path, 0, -3.0);  // clamped to the first key (identity)
  const OracleResult after = pose_or_fail(path, 0, 99.0);   // clamped to the last key (identity)
  for (int v = 0; v < 10; ++v) {
    const auto i = static_cast<size_t>(v);
    expect_near(mid.positions[i], simple_skin_expected(v, 0), 1e-12, v);
    expect_near(later.positions[i], simple_skin_expected(v, angle), 1e-12, v);
    expect_near(before.positions[i], simple_skin_expected(v, 0), 1e-12, v);
    expect_near(after.positions[i], simple_skin_expected(v, 0), 1e-12, v);
  }
}

struct Asset {
  const char* file;
  size_t vertices;
  int animations;
  int renormalized;
};

void PrintTo(const Asset& asset, std::ostream* out) { *out << asset.file; }

class GltfOracleAssets : public ::testing::TestWithParam<Asset> {};

TEST_P(GltfOracleAssets, EveryAnimationSamplesToFiniteShapesAtStartMiddleAndEnd) {
  const Asset asset = GetParam();
  const std::string path = data_file(asset.file);
  std::string error;
  const int count = animation_count(path, &error);
  ASSERT_EQ(count, asset.animations) << error;

  const OracleResult rest = pose_or_fail(path, -1, 0.0);
  ASSERT_EQ(rest.positions.size(), asset.vertices);
  EXPECT_EQ(rest.renormalized_vertices, asset.renormalized);
  ASSERT_TRUE(std::isfinite(rest.bbox_diagonal));
  ASSERT_GT(rest.bbox_diagonal, 0.0);
  std::cout << "[ oracle   ] " << asset.file << ": " << rest.positions.size() << " vertices, rest bbox diagonal "
            << rest.bbox_diagonal << ", renormalised " << rest.renormalized_vertices << ", animations " << count
            << "\n";

  for (int animation = 0; animation < count; ++animation) {
    double start = 0, end = 0;
    ASSERT_TRUE(animation_time_range(path, animation, &start, &end, &error)) << error;
    ASSERT_LE(start, end);
    for (double t : {start, 0.5 * (start + end), end}) {
      const OracleResult posed = pose_or_fail(path, animation, t);
      ASSERT_EQ(posed.positions.size(), asset.vertices);
      EXPECT_EQ(posed.bbox_diagonal, rest.bbox_diagonal);  // a rest-pose measure, whatever the time
      EXPECT_EQ(posed.renormalized_vertices, asset.renormalized);
      for (size_t v = 0; v < posed.positions.size(); ++v) {
        ASSERT_TRUE(posed.positions[v].allFinite()) << asset.file << " vertex " << v << " t " << t;
        // Animations move limbs, they do not fling vertices far off the model.
        ASSERT_LT((posed.positions[v] - rest.positions[v]).norm(), 5 * rest.bbox_diagonal) << "vertex " << v;
      }
      ASSERT_TRUE(posed.normals.empty() || posed.normals.size() == asset.vertices);
      for (const Eigen::Vector3d& n : posed.normals) ASSERT_NEAR(n.norm(), 1.0, 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Assets, GltfOracleAssets,
                         ::testing::Values(Asset{"SimpleSkin.gltf", 10, 1, 0}, Asset{"RiggedSimple.glb", 96, 1, 0},
                                           Asset{"RiggedFigure.glb", 370, 1, 31},
                                           Asset{"generic-hand_left.glb", 1360, 0, 0}),
                         [](const ::testing::TestParamInfo<Asset>& param_info) {
                           std::string name;
                           for (const char* c = param_info.param.file; *c != '.'; ++c)
                             if (std::isalnum(static_cast<unsigned char>(*c))) name += *c;
                           return name;
                         });

TEST(GltfOracleErrors, TruncatedGlbIsAnErrorNotACrash) {
  std::ifstream in(data_file("RiggedSimple.glb"), std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 11048u);
  const std::string path = testing::temp_path("cut_short.glb");
  for (size_t keep : {size_t{0}, size_t{4}, size_t{19}, size_t{20}, size_t{100}, bytes.size() / 2, bytes.size() - 4,
                      bytes.size() - 1}) {
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), static_cast<std::streamsize>(keep));
    }
    OracleResult result;
    std::string error;
    EXPECT_FALSE(skinned_pose(path, 0, 0.5, &result, &error)) << "kept " << keep << " bytes";
    const std::string expected = keep == 0 ? ": empty file" : ": truncated .glb";
    EXPECT_NE(error.find(expected), std::string::npos) << "kept " << keep << " bytes: " << error;
  }
  // Cut short but with the header and BIN chunk lengths patched to match: the
  // buffer's byteLength now exceeds the BIN chunk.
  std::vector<char> cut(bytes.begin(), bytes.end() - 2000);
  uint32_t json_length = 0;
  std::memcpy(&json_length, bytes.data() + 12, 4);
  const auto total = static_cast<uint32_t>(cut.size());
  const uint32_t bin_length = total - 28 - json_length;
  std::memcpy(cut.data() + 8, &total, 4);
  std::memcpy(cut.data() + 20 + json_length, &bin_length, 4);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(cut.data(), static_cast<std::streamsize>(cut.size()));
  }
  OracleResult result;
  std::string error;
  EXPECT_FALSE(skinned_pose(path, 0, 0.5, &result, &error));
  EXPECT_NE(error.find("not a readable glTF 2.0 binary"), std::string::npos) << error;
  std::remove(path.c_str());
}

TEST(GltfOracleErrors, MissingFileAndAnimationOutOfRange) {
  OracleResult result;
  std::string error;
  EXPECT_FALSE(skinned_pose(data_file("no-such-model.glb"), 0, 0, &result, &error));
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
  EXPECT_EQ(animation_count(data_file("no-such-model.glb"), &error), -1);

  EXPECT_FALSE(skinned_pose(data_file("RiggedSimple.glb"), 1, 0, &result, &error));
  EXPECT_NE(error.find("animation 1 out of range"), std::string::npos) << error;
  EXPECT_FALSE(skinned_pose(data_file("generic-hand_left.glb"), 0, 0, &result, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
  double start = 0, end = 0;
  EXPECT_FALSE(animation_time_range(data_file("generic-hand_left.glb"), 0, &start, &end, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
}

}  // namespace
}  // namespace sinew::oracle
