// sinew's fixed-point glTF pipeline (GltfPoser, sinew-pose) against the
// independent double-precision oracle, on every rigged asset in tests/data:
// every animation, sampled at 41 times (mostly between keyframes); the largest position error divided by
// the rest-pose bounding-box diagonal must stay within 2e-5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "gltf_oracle.hpp"
#include "host_tools/rigc/gltf_poser.hpp"
#include "synthetic_gltf.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<std::string> rigged_assets() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(SINEW_TEST_DATA_DIR)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".glb" || ext == ".gltf") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(PoseVsOracle, EveryAssetEveryAnimationWithinTwoE5OfTheDiagonal) {
  const auto assets = rigged_assets();
  ASSERT_GE(assets.size(), 4u);
  int compared = 0;
  for (const std::string& path : assets) {
    std::string error;
    const int animations = sinew::oracle::animation_count(path, &error);
    ASSERT_GE(animations, 0) << error;
    sinew::rigc::GltfPoser poser;
    ASSERT_TRUE(poser.open(path, &error)) << path << ": " << error;
    double worst = 0, diagonal = 0;
    int samples = 0;
    // Assets without animations are still compared at their rest pose.
    for (int a = (animations == 0 ? -1 : 0); a < std::max(animations, 0); ++a) {
      double start = 0, end = 0;
      if (a >= 0) ASSERT_TRUE(sinew::oracle::animation_time_range(path, a, &start, &end, &error)) << error;
      // 41 times: both ends plus 39 that fall between keyframes (a prime step).
      for (int k = 0; k <= 40; ++k) {
        const double t = start + (end - start) * k / 40.0 + (k % 40 != 0 ? (end - start) * 0.0037 : 0.0);
        sinew::oracle::OracleResult ref;
        ASSERT_TRUE(sinew::oracle::skinned_pose(path, a, t, &ref, &error)) << path << ": " << error;
        std::vector<std::array<double, 3>> got;
        ASSERT_TRUE(poser.pose(a, t, &got, &error)) << path << ": " << error;
        ASSERT_EQ(got.size(), ref.positions.size()) << path;
        for (size_t v = 0; v < got.size(); ++v)
          for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::fabs(got[v][static_cast<size_t>(c)] - ref.positions[v][c]));
        diagonal = ref.bbox_diagonal;
        ++samples;
      }
    }
    std::printf(
        "pose vs oracle: %-24s %2d animation(s), %3d samples, %5zu vertices, max error %.3g = %.3g of the bbox "
        "diagonal\n",
        fs::path(path).filename().c_str(), animations, samples,
        poser.model().meshes.empty() ? size_t{0} : static_cast<size_t>(poser.report().vertices), worst,
        worst / diagonal);
    EXPECT_LE(worst / diagonal, 2e-5) << path;
    ++compared;
  }
  EXPECT_EQ(compared, static_cast<int>(assets.size()));
}

TEST(PoseVsOracle, RenormalisedWeightsAreReportedLikeTheOracle) {
  const std::string path = std::string(SINEW_TEST_DATA_DIR) + "/RiggedFigure.glb";
  sinew::rigc::GltfPoser poser;
  std::string error;
  ASSERT_TRUE(poser.open(path, &error)) << error;
  EXPECT_EQ(poser.report().renormalized_vertices, 31u);
}

TEST(PoseVsOracle, MalformedInputsAreRejectedWithAMessage) {
  std::string error;
  sinew::rigc::GltfPoser hand;
  ASSERT_TRUE(hand.open(std::string(SINEW_TEST_DATA_DIR) + "/generic-hand_left.glb", &error)) << error;
  std::vector<std::array<double, 3>> out;
  EXPECT_FALSE(hand.pose(0, 0.0, &out, &error));
  EXPECT_NE(error.find("no such animation"), std::string::npos) << error;

  // A .glb cut in half.
  std::ifstream in(std::string(SINEW_TEST_DATA_DIR) + "/RiggedSimple.glb", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = sinew::oracle::testing::temp_path("truncated.glb");
  std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  sinew::rigc::GltfPoser truncated;
  error.clear();
  EXPECT_FALSE(truncated.open(cut, &error));
  EXPECT_FALSE(error.empty());
  std::printf("truncated .glb: %s\n", error.c_str());
}

namespace {

// One triangle skinned to two joints; `joints_per_vertex` influences per vertex.
std::string synthetic_skin(const std::string& name, int influence_sets, int ibm_count) {
  sinew::oracle::testing::GltfBuilder b;
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int pv = b.add_view(pos);
  const int pa = b.add_accessor(pv, 5126, 3, "VEC3", {{"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
  nlohmann::json attributes = {{"POSITION", pa}};
  for (int set = 0; set < influence_sets; ++set) {
    const std::vector<uint16_t> j(12, static_cast<uint16_t>(set % 2));
    const std::vector<float> w(12, 1.0f / static_cast<float>(4 * influence_sets));
    attributes["JOINTS_" + std::to_string(set)] = b.add_accessor(b.add_view(j), 5123, 3, "VEC4");
    attributes["WEIGHTS_" + std::to_string(set)] = b.add_accessor(b.add_view(w), 5126, 3, "VEC4");
  }
  std::vector<float> ibm;
  for (int m = 0; m < ibm_count; ++m) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  const int ia = b.add_accessor(b.add_view(ibm), 5126, static_cast<size_t>(ibm_count), "MAT4");
  b.doc["meshes"] = {{{"primitives", {{{"attributes", attributes}}}}}};
  b.doc["nodes"] = {{{"mesh", 0}, {"skin", 0}}, {{"children", {2}}}, {{"translation", {1, 0, 0}}}};
  b.doc["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", ia}}};
  b.doc["scenes"] = {{{"nodes", {0, 1}}}};
  b.doc["scene"] = 0;
  return b.write(name);
}

}  // namespace

TEST(PoseVsOracle, MoreThanEightInfluencesAreRejected) {
  sinew::rigc::GltfPoser ok, too_many;
  std::string error;
  EXPECT_TRUE(ok.open(synthetic_skin("eight.gltf", 2, 2), &error)) << error;
  error.clear();
  EXPECT_FALSE(too_many.open(synthetic_skin("twelve.gltf", 3, 2), &error));
  EXPECT_NE(error.find("more than 8 influences"), std::string::npos) << error;
  std::printf("12 influences: %s\n", error.c_str());
}

TEST(PoseVsOracle, MissingInverseBindMatricesAreRejected) {
  sinew::rigc::GltfPoser p;
  std::string error;
  EXPECT_FALSE(p.open(synthetic_skin("one_ibm.gltf", 1, 1), &error));
  EXPECT_NE(error.find("fewer inverse bind matrices than joints"), std::string::npos) << error;
  std::printf("1 IBM for 2 joints: %s\n", error.c_str());
}

TEST(PoseVsOracle, SinewPoseCommandWritesTheDocumentedCsv) {
  const std::string out = sinew::oracle::testing::temp_path("pose.csv");
  const std::string model = std::string(SINEW_TEST_DATA_DIR) + "/RiggedFigure.glb";
  const std::string cmd = std::string(SINEW_POSE_EXE) + " " + model + " --animation 0 --time 0.6 --out " + out;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream csv(out);
  std::string line;
  std::vector<std::array<double, 3>> rows;
  while (std::getline(csv, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::array<double, 3> p{};
    char c1 = 0, c2 = 0;
    std::istringstream(line) >> p[0] >> c1 >> p[1] >> c2 >> p[2];
    ASSERT_EQ(c1, ',');
    rows.push_back(p);
  }
  sinew::oracle::OracleResult ref;
  std::string error;
  ASSERT_TRUE(sinew::oracle::skinned_pose(model, 0, 0.6, &ref, &error)) << error;
  ASSERT_EQ(rows.size(), ref.positions.size());
  double worst = 0;
  for (size_t v = 0; v < rows.size(); ++v)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(rows[v][static_cast<size_t>(c)] - ref.positions[v][c]));
  EXPECT_LE(worst / ref.bbox_diagonal, 2e-5);
}
