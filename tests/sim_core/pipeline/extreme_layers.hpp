// The layer sections of a compiled blob pushed to the limits their loaders
// accept (docs/rig-format.md, "Layer sections"; each layer's validator):
// gains, counts of iterations and stiffnesses at their maxima, and the
// positions, extents and transforms the validators leave unchecked (or check
// against a coordinate limit) at that limit. Each edit keeps the blob
// loadable; tests/sim_core/pipeline/extreme_layers_test.cpp runs every layer on them.
#pragma once

#include "tests/sim_core/pipeline/extreme_blob.hpp"

namespace sinew::test {

constexpr int32_t kUnitMax = fx::kUnitOne;
constexpr int32_t kCoord = int32_t{1} << 30;  // metaballs' coordinate limit

inline fx::Vec3 extreme_vec(size_t i) { return {extreme(i, 0), extreme(i, 1), extreme(i, 2)}; }
inline fx::Vec3 coord_vec(size_t i) {
  return {(i % 2) ? kCoord : -kCoord, (i % 2) ? -kCoord : kCoord, (i % 3) ? kCoord : -kCoord};
}

inline void extreme_mat34(fx::Mat34& m, size_t i) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m.m[r][c] = extreme(i + static_cast<size_t>(r), static_cast<size_t>(c));
    m.t[r] = extreme(i, static_cast<size_t>(r) + 1);
  }
}

// SPH: every gain at the top of its range, the load gain and the kernel
// radius at INT32_MAX (every particle is every other's neighbour), the load
// point at the extremes; wide = false instead takes h = 1 (grid_radius 32:
// the largest 64-cell grid), Tresca limits of one LSB and particles and
// skin at +-(2^31 - 1).
inline void push_sph(std::vector<uint8_t>* bytes, bool wide) {
  for (uint32_t inst = 0; inst < pipeline::kMaxSphJoints; ++inst) {
    const LayerView v = layer_view(*bytes, sinew::sph::kSectionSphJoint, inst);
    if (!v) return;
    // The built sections are version 1 (no surface tension): rewritten as
    // version 2 with the tension gain at its maximum too.
    sinew::sph::SphSectionParamsV1 v1;
    std::memcpy(&v1, bytes->data() + v.params, sizeof v1);
    sinew::sph::SphSectionParams v2{};
    std::memcpy(static_cast<void*>(&v2.params), v1.params, sizeof v1.params);
    v2.joint = v1.joint;
    v2.force_input = v1.force_input;
    std::memcpy(bytes->data() + v.params, &v2, sizeof v2);
    std::memcpy(bytes->data() + v.section, &sinew::sph::kSphSectionVersion2, sizeof(uint32_t));
    edit_record<sinew::sph::SphSectionParams>(
        bytes, v.params,
        [&](sinew::sph::SphSectionParams& p, size_t) {
          p.params.substeps = sph::kMaxSubsteps;
          p.params.max_neighbours = sph::kMaxNeighbours;
          p.params.elastic_gain = p.params.pressure_gain = p.params.viscosity_gain = kUnitMax - 1;
          p.params.tension_gain = kUnitMax - 1;
          p.params.damping = kUnitMax;
          p.params.load_gain = INT32_MAX;
          p.params.h = wide ? INT32_MAX : 1;
          p.params.grid_radius = wide ? INT32_MAX : 32;
          p.params.tau_f = wide ? INT32_MAX : 1;
          p.params.yield_count = wide ? v.count(6) : 1;
          p.joint.load_point = extreme_vec(inst);
        },
        0);
    if (wide) continue;
    for (uint32_t a : {0u, 1u, 2u, 3u, 4u, 5u, 8u, 9u, 10u})
      edit_array<int32_t>(bytes, v, a, [&](int32_t& x, size_t i) { x = extreme(i / 3, a % 3); });
  }
}

// Metaballs: iteration counts and rates at their maxima, every coordinate at
// the validator's +-2^30, radii and rest lengths at 2^30, stiffnesses 1, and
// the inverse binds (unchecked) at the Lin and Len extremes.
inline void push_metaballs(std::vector<uint8_t>* bytes) {
  namespace mb = metaballs;
  const LayerView v = layer_view(*bytes, sinew::metaballs::kSectionMetaballs);
  if (!v) return;
  edit_record<sinew::metaballs::MetaballsSectionParams>(
      bytes, v.params,
      [](sinew::metaballs::MetaballsSectionParams& p, size_t) {
        p.pbd_iterations = mb::kMaxPbdIterations;
        p.jiggle_damping = kUnitMax - 1;
        p.smoothing_passes = mb::kMaxSmoothingPasses;
        p.smoothing_rate = kUnitMax;
      },
      0);
  edit_array<fx::Mat34>(bytes, v, 0, [](fx::Mat34& m, size_t i) { extreme_mat34(m, i); });
  edit_array<fx::Vec3>(bytes, v, 1, [](fx::Vec3& c, size_t i) { c = coord_vec(i); });
  edit_array<fx::Len>(bytes, v, 2, [](fx::Len& r, size_t) { r = kCoord; });
  edit_array<fx::Unit>(bytes, v, 6, [](fx::Unit& k, size_t i) { k = (i % 2) ? kUnitMax : 1; });
  edit_array<mb::BallPair>(bytes, v, 7, [](mb::BallPair& p, size_t i) {
    p.rest = (i % 2) ? kCoord : 1;
    p.stiffness = kUnitMax;
  });
  edit_array<mb::BulgeRecord>(bytes, v, 8, [](mb::BulgeRecord& b, size_t) { b.gain = kUnitMax - 1; });
  edit_array<fx::Vec3>(bytes, v, 11, [](fx::Vec3& d, size_t i) { d = coord_vec(i + 1); });
  edit_array<mb::JointBall>(bytes, v, 12, [](mb::JointBall& b, size_t i) { b.rest_center = coord_vec(i); });
  edit_array<fx::Vec3>(bytes, v, 17, [](fx::Vec3& d, size_t i) { d = coord_vec(i); });
  edit_array<fx::Vec3>(bytes, v, 18, [](fx::Vec3& d, size_t i) { d = coord_vec(i + 1); });
}

// Muscles: attachment and pivot points at +-(2^31 - 1), slice radii and
// bulges at INT32_MAX, rest lengths of one LSB; primitives centred at the
// extremes with extents at INT32_MAX (aspect 1) or, every other one, of one
// LSB.
inline void push_muscles(std::vector<uint8_t>* bytes) {
  namespace mu = muscle;
  const LayerView v = layer_view(*bytes, sinew::muscle::kSectionMuscles);
  if (!v) return;
  edit_array<mu::MuscleRecord>(bytes, v, 0, [](mu::MuscleRecord& m, size_t i) {
    for (int k = 0; k < 2; ++k) {
      m.origin[k].local = extreme_vec(i + static_cast<size_t>(k));
      m.insertion[k].local = extreme_vec(i + static_cast<size_t>(k) + 1);
    }
    m.pivot_local = extreme_vec(i);
    for (uint32_t s = 0; s < mu::kSlices; ++s) {
      m.half_width[s] = m.half_thickness[s] = INT32_MAX;
      m.bulge[s] = extreme(i, s);
    }
    m.rest_length = 1;
  });
  edit_array<mu::PrimitiveRecord>(bytes, v, 1, [](mu::PrimitiveRecord& p, size_t i) {
    p.centre = extreme_vec(i);
    for (fx::Len& e : p.extent) e = (i % 2) ? 1 : INT32_MAX;
  });
}

// Elastic skin: iterations, Newton steps, stiffnesses and gains at their
// maxima, the collision radius, fat and edge rest lengths at INT32_MAX,
// anchors' points and (unchecked) normals at +-(2^31 - 1), trilinear
// parameters at their bounds.
inline void push_skin(std::vector<uint8_t>* bytes, uint32_t iterations) {
  namespace es = elastic_skin;
  const LayerView v = layer_view(*bytes, sinew::elastic_skin::kSectionElasticSkin);
  if (!v) return;
  edit_record<sinew::elastic_skin::SkinSectionParams>(
      bytes, v.params,
      [&](sinew::elastic_skin::SkinSectionParams& p, size_t) {
        p.params.iterations = iterations;
        p.params.push_back = kUnitMax;
        p.params.compression_band = 1;
        p.params.collision_radius = INT32_MAX;
        p.params.reaction_gain = kUnitMax;
        p.params.newton_steps = es::kMaxNewtonSteps;
        p.params.warm_start = 1;
      },
      0);
  edit_array<es::Anchor>(bytes, v, 0, [](es::Anchor& a, size_t i) {
    a.local_a = extreme_vec(i);
    a.local_b = extreme_vec(i + 1);
    a.normal_a = extreme_vec(i + 1);
    a.normal_b = extreme_vec(i);
    a.param[0] = (i % 2) ? es::kMaxAnchorST : -es::kMaxAnchorST;
    a.param[1] = (i % 2) ? -es::kMaxAnchorST : es::kMaxAnchorST;
    a.param[2] = (i % 2) ? es::kMaxAnchorU : es::kMinAnchorU;
  });
  edit_array<es::Stiffness>(bytes, v, 1, [](es::Stiffness& k, size_t) { k = es::kMaxStiffness; });
  edit_array<fx::Len>(bytes, v, 2, [](fx::Len& f, size_t) { f = INT32_MAX; });
  edit_array<es::Edge>(bytes, v, 3, [](es::Edge& e, size_t i) {
    e.rest = (i % 2) ? INT32_MAX : 0;
    e.k = es::kMaxStiffness;
  });
  edit_array<es::RubberBand>(bytes, v, 4, [](es::RubberBand& b, size_t) { b.k = es::kMaxStiffness; });
}

// Bar-net: inverse binds (unchecked) at the Lin and Len extremes, node rest
// positions and load forces at +-(2^31 - 1), load angle ranges of one LSB and
// of the whole circle, wrap offsets at the extremes and barycentrics far
// outside [0, 1] (they only need to sum to 2^30).
inline void push_barnet(std::vector<uint8_t>* bytes) {
  namespace bn = sinew::barnet;
  for (uint32_t inst = 0; inst < pipeline::kMaxBarnets; ++inst) {
    const LayerView v = layer_view(*bytes, sinew::barnet::kSectionBarnet, inst);
    if (!v) return;
    edit_array<fx::Mat34>(bytes, v, 0, [](fx::Mat34& m, size_t i) { extreme_mat34(m, i); });
    edit_array<bn::NodeRecord>(bytes, v, 1, [](bn::NodeRecord& n, size_t i) { n.rest = extreme_vec(i); });
    edit_array<bn::LoadRecord>(bytes, v, 3, [](bn::LoadRecord& l, size_t i) {
      l.force = extreme_vec(i);
      l.angle_lo = (i % 2) ? INT32_MIN : 0;
      l.angle_hi = (i % 2) ? INT32_MAX : 1;
    });
    edit_array<bn::WrapRecord>(bytes, v, 5, [](bn::WrapRecord& w, size_t i) {
      w.offset = extreme(i, 0);
      w.bary[0] = INT32_MAX;
      w.bary[1] = fx::kUnitOne - INT32_MAX;
      w.bary[2] = 0;
    });
  }
}

}  // namespace sinew::test
