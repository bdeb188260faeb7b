// sinew-pose --spec: a glTF animation played through the pipeline with the
// spec's layers. A bar-net alone moves only the vertices it wraps (the rest
// match plain skinning bit for bit); every layer at once gives finite
// positions that differ from plain skinning.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "host_tools/rigc/gltf_poser.hpp"

namespace {

const std::string kData = SINEW_TEST_DATA_DIR;

std::vector<std::array<double, 3>> pose(sinew::rigc::GltfPoser* p, double t) {
  std::vector<std::array<double, 3>> out;
  std::string error;
  EXPECT_TRUE(p->pose(0, t, &out, &error)) << error;
  return out;
}

}  // namespace

TEST(PoseSpec, ABarnetAloneMovesOnlyItsWrappedVertices) {
  const std::string spec = kData + "/pose_spec_barnet.toml";
  std::ofstream(spec) << "[rig]\nsource = \"RiggedFigure.glb\"\nskinning = \"lbs\"\n[[barnet]]\njoint = 4\n";
  sinew::rigc::GltfPoser plain, layered;
  std::string error;
  ASSERT_TRUE(plain.open(kData + "/RiggedFigure.glb", &error)) << error;
  ASSERT_TRUE(layered.open_spec(spec, 100, &error)) << error;
  std::remove(spec.c_str());
  ASSERT_EQ(layered.layers().barnet.count, 1u);
  size_t wrapped = layered.layers().barnet.net[0].wrap.size(), moved = 0, moved_outside = 0;
  std::vector<bool> in_wrap(1u << 16, false);
  for (const auto& w : layered.layers().barnet.net[0].wrap) in_wrap[w.vertex] = true;
  for (double t : {0.3, 0.8, 1.2}) {
    const auto a = pose(&plain, t), b = pose(&layered, t);
    ASSERT_EQ(a.size(), b.size());
    for (size_t v = 0; v < a.size(); ++v) {
      const bool differs = a[v] != b[v];
      moved += differs ? 1 : 0;
      moved_outside += differs && !in_wrap[v] ? 1 : 0;
    }
  }
  std::printf("pose --spec bar-net: %zu vertex poses moved over 3 times (%zu wrapped vertices), %zu outside\n", moved,
              wrapped, moved_outside);
  EXPECT_EQ(moved_outside, 0u);
  EXPECT_GT(moved, 0u) << "the walk bends the knee: the net's loads act";
}

TEST(PoseSpec, EveryLayerGivesFinitePositions) {
  sinew::rigc::GltfPoser plain, layered;
  std::string error;
  ASSERT_TRUE(plain.open(kData + "/RiggedFigure.glb", &error)) << error;
  ASSERT_TRUE(layered.open_spec(kData + "/rigged_figure_layers.toml", 100, &error)) << error;
  EXPECT_EQ(layered.layer_report().size(), 8u);
  size_t differ = 0;
  double largest = 0;
  for (double t : {0.2, 0.6, 1.0}) {
    const auto a = pose(&plain, t), b = pose(&layered, t);
    ASSERT_EQ(a.size(), b.size());
    for (size_t v = 0; v < a.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(b[v][static_cast<size_t>(c)]));
        const double d = std::abs(a[v][static_cast<size_t>(c)] - b[v][static_cast<size_t>(c)]);
        differ += d > 0 ? 1 : 0;
        largest = std::max(largest, d);
      }
  }
  std::printf("pose --spec every layer: %zu coordinates differ from plain skinning, largest %.4f units\n", differ,
              largest);
  EXPECT_GT(differ, 0u);
  EXPECT_LT(largest, 1.0) << "the figure is about 2 units tall; the layers reshape it, they do not tear it";
}

TEST(PoseSpec, ASpecWithoutAGltfSourceIsRefused) {
  sinew::rigc::GltfPoser p;
  std::string error;
  const std::string spec = kData + "/pose_spec_builtin.toml";
  std::ofstream(spec) << "[rig]\nsource = \"builtin:arm\"\n";
  EXPECT_FALSE(p.open_spec(spec, 100, &error));
  std::remove(spec.c_str());
  EXPECT_NE(error.find("[rig] source must be a glTF model"), std::string::npos) << error;
}
