// The node-skinning AVX2 kernel (sim_core/barnet/node_skinning_avx2.cpp)
// against the scalar specification (node_skinning.cpp), word for word and
// saturation count for saturation count: on adversarial nets (matrices
// anywhere in int32, rest positions and directions inside and beyond the
// plain transforms' bounds, rest loads large enough to clamp, bones that
// cancel a direction to zero, free-node counts that are not a multiple of
// the lane width). The arm's nets through whole steps are compared in
// barnet_wrap_kernel_test.cpp.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "sim_core/barnet/node_skinning.hpp"
#include "sim_core/fixed/mat34.hpp"

namespace node_skinning_kernel_test {
namespace {

namespace bn = sinew::barnet;
namespace bd = sinew::barnet::detail;
namespace fx = sinew::fx;

bool avx2_available() { return bn::vector_kernel_supported(bn::VectorKernel::kAvx2); }

int32_t any_i32(std::mt19937_64& rng) { return static_cast<int32_t>(static_cast<uint32_t>(rng())); }

// Near INT32_MAX or INT32_MIN: with such matrix entries, three products
// of one row come near 2^62 each and their sum leaves int64 unless the
// transform saturates.
int32_t extreme(std::mt19937_64& rng) {
  return rng() & 1 ? INT32_MAX - static_cast<int32_t>(rng() % 4) : INT32_MIN + static_cast<int32_t>(rng() % 4);
}

// A coordinate inside the plain bound (mostly), at it, or beyond it.
int32_t coordinate(std::mt19937_64& rng, int32_t limit) {
  switch (rng() % 8) {
    case 0:
      return any_i32(rng);
    case 7:
      return extreme(rng);
    case 1:
      return rng() & 1 ? limit - static_cast<int32_t>(rng() % 3) + 1 : -limit + static_cast<int32_t>(rng() % 3) - 1;
    default:
      return static_cast<int32_t>(static_cast<int64_t>(rng() % (2 * uint64_t(limit) + 1)) - limit);
  }
}

// A matrix entry: anywhere in int32, at its limits, a Q.24 rotation-like
// value, or zero.
int32_t entry(std::mt19937_64& rng) {
  switch (rng() % 5) {
    case 0:
      return any_i32(rng);
    case 4:
      return extreme(rng);
    case 1:
      return 0;
    default:
      return static_cast<int32_t>(rng() % (int64_t{2} << 24)) - (int32_t{1} << 24);
  }
}

struct Net {
  uint32_t joints = 0, free = 0;
  std::vector<bn::NodeRecord> nodes;
  std::vector<fx::Mat34> skin;
  std::vector<fx::Vec3> rest_direction;
  std::vector<int64_t> rest_magnitude;
};

Net random_net(std::mt19937_64& rng, uint32_t node_count, uint32_t free) {
  Net net;
  net.joints = 1 + static_cast<uint32_t>(rng() % 9);
  net.free = free;
  net.skin.resize(net.joints);
  for (fx::Mat34& a : net.skin) {
    for (auto& row : a.m)
      for (int32_t& v : row) v = entry(rng);
    for (int32_t& v : a.t) v = rng() % 4 == 0 ? any_i32(rng) : static_cast<int32_t>(rng() % 2000001) - 1000000;
  }
  if (rng() % 4 == 0 && net.joints >= 2) {  // two opposite bones: a direction can cancel to zero
    net.skin[1] = net.skin[0];
    for (auto& row : net.skin[1].m)
      for (int32_t& v : row) v = v == INT32_MIN ? INT32_MAX : -v;
  }
  net.nodes.resize(node_count);
  for (bn::NodeRecord& n : net.nodes) {
    n.rest = {coordinate(rng, fx::kPlainPointLimit), coordinate(rng, fx::kPlainPointLimit),
              coordinate(rng, fx::kPlainPointLimit)};
    n.influence_count = static_cast<uint8_t>(1 + rng() % bn::kMaxNodeInfluences);
    int64_t left = fx::kUnitOne;
    for (uint32_t k = 0; k < n.influence_count; ++k) {
      n.joint[k] = static_cast<uint16_t>(rng() % net.joints);
      const int64_t w = k + 1 == n.influence_count ? left : static_cast<int64_t>(rng() % (uint64_t(left) + 1));
      n.weight[k] = static_cast<fx::Unit>(w);
      left -= w;
    }
    if (net.joints >= 2 && rng() % 4 == 0 && n.influence_count >= 2) {  // half and half on the opposite bones
      n.joint[0] = 0, n.joint[1] = 1;
      n.weight[0] = fx::kUnitOne / 2, n.weight[1] = fx::kUnitOne / 2;
      for (uint32_t k = 2; k < n.influence_count; ++k) n.weight[k] = 0;
    }
  }
  for (uint32_t i = 0; i < free; ++i) {
    net.rest_direction.push_back({coordinate(rng, fx::kPlainVectorLimit), coordinate(rng, fx::kPlainVectorLimit),
                                  coordinate(rng, fx::kPlainVectorLimit)});
    net.rest_magnitude.push_back(rng() % 4 == 0 ? static_cast<int64_t>(rng() >> 1)  // up to 2^63: clamps
                                                : static_cast<int64_t>(rng() >> (2 + rng() % 40)));
  }
  return net;
}

struct Words {
  std::vector<int32_t> node[3], skinned[3];
  std::vector<int64_t> load[3];
  std::vector<bn::SkinColumns> columns;
  uint32_t saturated = 0;
};

Words skin_by(const Net& net, bn::VectorKernel kernel) {
  Words w;
  bn::BarnetModel model;
  model.nodes = net.nodes;
  model.joint_count = net.joints;
  std::vector<fx::Mat34> skin = net.skin;
  std::vector<fx::Vec3> direction = net.rest_direction;
  std::vector<int64_t> magnitude = net.rest_magnitude;
  w.columns.resize(net.joints);
  bn::BarnetState st;
  st.model = &model;
  st.free_count = net.free;
  st.skin = skin;
  st.skin_columns = w.columns;
  st.rest_direction = direction;
  st.rest_magnitude = magnitude;
  std::span<fx::Len> node[3];
  for (size_t c = 0; c < 3; ++c) {
    w.node[c].assign(net.nodes.size(), 7);  // overwritten by both
    w.skinned[c].assign(net.free, 7);
    w.load[c].assign(net.free, 7);
    node[c] = w.node[c];
    st.skinned[c] = w.skinned[c];
    st.load[c] = w.load[c];
  }
  fx::Saturation sat;
  bd::skin_nodes(model, &st, node, sat, kernel);
  w.saturated = sat.events;
  w.columns.clear();  // the kernel's scratch, not a result
  return w;
}

}  // namespace
}  // namespace node_skinning_kernel_test

using namespace node_skinning_kernel_test;

TEST(BarnetNodeSkinningKernel, MatchesTheSpecificationOnAdversarialNets) {
  if (!node_skinning_kernel_test::avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  std::mt19937_64 rng(20261205);
  uint32_t saturating = 0, beyond_bounds = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const uint32_t nodes = 1 + static_cast<uint32_t>(rng() % 23);
    const Net net = random_net(rng, nodes, static_cast<uint32_t>(rng() % (nodes + 1)));
    const Words vector = skin_by(net, bn::VectorKernel::kAvx2), scalar = skin_by(net, bn::VectorKernel::kScalar);
    for (size_t c = 0; c < 3; ++c) {
      ASSERT_EQ(vector.node[c], scalar.node[c]) << "trial " << trial << " axis " << c;
      ASSERT_EQ(vector.skinned[c], scalar.skinned[c]) << "trial " << trial << " axis " << c;
      ASSERT_EQ(vector.load[c], scalar.load[c]) << "trial " << trial << " axis " << c;
    }
    ASSERT_EQ(vector.saturated, scalar.saturated) << "trial " << trial;
    saturating += scalar.saturated != 0;
    for (const bn::NodeRecord& n : net.nodes) beyond_bounds += !fx::within(n.rest, fx::kPlainPointLimit);
  }
  // The cases the kernel must get right were drawn.
  EXPECT_GT(saturating, 300u);
  EXPECT_GT(beyond_bounds, 1000u);
}
