// Internal to sim_core/skin: what every vector DQS kernel shares besides its
// lanes: the job, the rigid runs' cache, and the loop that gathers DQS
// vertices into groups of the kernel's width. Include it inside the kernel's
// ISA region (isa_region.hpp), after the kernel's own includes: the loop is
// then compiled for the kernel's extension and inlines its stages; internal
// linkage keeps each kernel's copy its own.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

#include "skinning_detail.hpp"

namespace sinew::skin::detail {
namespace {

struct DualJob {
  const rig::Rig* rig;
  std::span<const fx::DualQuat> dual;
  const SkinnedVertices* out;
  uint32_t first;
  bool normals;
};

// Rigid runs: kLanes consecutive DQS vertices with weight 1 on one and the
// same palette entry (every other weight 0). The specification's blend is
// then that entry itself, word for word (2^30 q rounded back by 30 bits,
// the zero weights adding nothing whatever their hemisphere), so its
// normalisation, rotation and translation (dual_motion) are made once per
// entry and call, by the specification's own function (whatever path
// normalize_fast takes), and only the transform runs per vertex. An entry
// is kept for this when the transform's saturating adds cannot saturate
// (|R p| < 2^62 from the rows' sums of magnitudes below 2^31, and |t| <
// 2^61); otherwise its runs take the general path.
constexpr size_t kMaxRigidPalette = 256;

struct RigidEntry {
  int32_t rotation[3][3];
  int64_t t[3];
};

struct RigidCache {
  RigidEntry entry[kMaxRigidPalette];
  uint8_t state[kMaxRigidPalette];  // 0 not made, 1 usable, 2 not usable
};

inline bool rigid_entry(const DualJob& job, RigidCache* cache, uint32_t j) {
  if (cache->state[j] == 0) {
    bool usable = true;
    const DualMotion m = dual_motion(job.dual[j]);
    RigidEntry& e = cache->entry[j];
    for (int i = 0; i < 3; ++i) {
      int64_t row = 0;
      for (int k = 0; k < 3; ++k) {
        e.rotation[i][k] = m.rotation.m[i][k];
        row += m.rotation.m[i][k] < 0 ? -int64_t{m.rotation.m[i][k]} : int64_t{m.rotation.m[i][k]};
      }
      e.t[i] = m.t[i];
      const int64_t limit = int64_t{1} << 61;
      usable = usable && row < (int64_t{1} << 31) && m.t[i] < limit && m.t[i] > -limit;
    }
    cache->state[j] = usable ? 1 : 2;
  }
  return cache->state[j] == 1;
}

// Whether vertices v .. v + Lanes - 1 (all DQS) are a rigid run of one
// entry: its index in *entry.
template <uint32_t K, uint32_t Lanes>
inline bool rigid_run(const rig::Rig& rig, uint32_t v, uint16_t* entry) {
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * K;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * K;
  bool rigid = true;
  for (uint32_t l = 0; l < Lanes; ++l) {
    rigid = rigid && weights[l * K] == fx::kUnitOne && joints[l * K] == joints[0];
    for (uint32_t k = 1; k < K; ++k) rigid = rigid && weights[l * K + k] == 0;
  }
  *entry = joints[0];
  return rigid;
}

// The DQS vertices of [first, first + count) in groups of the kernel's
// width (Group's v[kLanes], n and checks), GroupsPerBlock groups at a time
// through RunBlock(job, groups, count); rigid runs of kLanes vertices through
// RigidTransform(job, entry, v). A last group of fewer repeats its last
// vertex in the spare lanes (computed, not stored).
template <uint32_t K, typename Group, uint32_t GroupsPerBlock, auto RunBlock, auto RigidTransform>
void run_dual_groups(const DualJob& job, uint32_t count) {
  constexpr uint32_t kLanes = sizeof(Group::v) / sizeof(Group::v[0]);
  static_assert(kLanes == 4 || kLanes == 8);
  using MethodWord = std::conditional_t<kLanes == 4, uint32_t, uint64_t>;
  constexpr MethodWord kAllDual =
      static_cast<MethodWord>(0x0101010101010101u) * static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion);
  const rig::Rig& rig = *job.rig;
  RigidCache rigid;
  const bool rigid_runs = job.dual.size() <= kMaxRigidPalette;
  if (rigid_runs) std::memset(rigid.state, 0, sizeof(rigid.state));
  Group groups[GroupsPerBlock];
  uint32_t full = 0;  // groups of the block filled
  uint32_t n = 0;     // vertices in groups[full]
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t vertex = job.first + i;
    bool lanes_in_a_row = false;  // kLanes DQS vertices in a row: one full group
    if (n == 0 && count - i >= kLanes) {
      MethodWord methods;
      std::memcpy(&methods, rig.method.data() + vertex, sizeof(methods));
      lanes_in_a_row = methods == kAllDual;
    }
    uint16_t entry = 0;
    if (lanes_in_a_row && rigid_runs && rigid_run<K, kLanes>(rig, vertex, &entry) && rigid_entry(job, &rigid, entry)) {
      RigidTransform(job, rigid.entry[entry], vertex);
      i += kLanes - 1;
      continue;
    }
    if (lanes_in_a_row) {
      for (uint32_t l = 0; l < kLanes; ++l) groups[full].v[l] = vertex + l;
      n = kLanes;
      i += kLanes - 1;
    } else if (is_dual(rig, vertex)) {
      groups[full].v[n++] = vertex;
    } else {
      continue;
    }
    if (n < kLanes) continue;
    groups[full].n = kLanes;
    groups[full].checks = {};
    n = 0;
    if (++full == GroupsPerBlock) {
      RunBlock(job, groups, full);
      full = 0;
    }
  }
  if (n > 0) {
    Group& last = groups[full++];
    for (uint32_t l = n; l < kLanes; ++l) last.v[l] = last.v[n - 1];
    last.n = n;
    last.checks = {};
  }
  if (full > 0) RunBlock(job, groups, full);
}

}  // namespace
}  // namespace sinew::skin::detail
