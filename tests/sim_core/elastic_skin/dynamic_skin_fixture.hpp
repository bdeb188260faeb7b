// A small synthetic skin for the dynamic-mode tests: vertices anchored to
// one bone that only translates, optional edges, rubber bands to a fake
// muscle's fixed ring vertices, and optional primitives (frames set by the
// test). No rig, no builder: every input is set by hand.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/fixed/mat34.hpp"

namespace sinew::test {

inline fx::Len to_len(double units) { return static_cast<fx::Len>(std::llround(units * 1048576.0)); }
inline double from_len(int64_t len) { return static_cast<double>(len) / 1048576.0; }
inline int32_t to_q16(double v) { return static_cast<int32_t>(std::llround(v * 65536.0)); }
inline int32_t to_accel(double v) { return static_cast<int32_t>(std::llround(v * 256.0)); }  // Q24.8
inline int32_t to_q24(double v) { return static_cast<int32_t>(std::llround(v * 16777216.0)); }

class DynamicSkin {
 public:
  static constexpr uint32_t kRing = 4;  // fake muscle: one muscle, kSlices slices of 4 ring vertices

  DynamicSkin() {
    model.joint_count = 1;
    model.solver.mode = static_cast<uint8_t>(elastic_skin::SkinMode::kDynamic);
    model.params.push_back = fx::kUnitOne;  // compressed edges as stiff as stretched ones (linear springs)
    muscle_records.resize(1);
    bone = fx::mat34_identity();
  }
  DynamicSkin(const DynamicSkin&) = delete;  // spans point into this object
  DynamicSkin& operator=(const DynamicSkin&) = delete;

  uint32_t add_vertex(double x, double y, double z, double anchor_stiffness, double fat_thickness = 0) {
    elastic_skin::Anchor a;
    a.kind = static_cast<uint8_t>(elastic_skin::AnchorKind::kBone);
    a.local_a = a.local_b = {to_len(x), to_len(y), to_len(z)};
    // Outward normal: radial from the origin (the primitives in these tests
    // are centred there); +y when at the origin.
    const double r = std::sqrt(x * x + y * y + z * z);
    const double nx = r > 0 ? x / r : 0, ny = r > 0 ? y / r : 1, nz = r > 0 ? z / r : 0;
    a.normal_a = a.normal_b = {static_cast<int32_t>(std::llround(nx * 1073741824.0)),
                               static_cast<int32_t>(std::llround(ny * 1073741824.0)),
                               static_cast<int32_t>(std::llround(nz * 1073741824.0))};
    anchors.push_back(a);
    anchor_k.push_back(static_cast<elastic_skin::Stiffness>(to_q16(anchor_stiffness)));
    fat.push_back(to_len(fat_thickness));
    return static_cast<uint32_t>(anchors.size() - 1);
  }
  // A vertex whose anchor normal is the given unit vector instead of the radial one.
  uint32_t add_vertex_with_normal(double x, double y, double z, double nx, double ny, double nz,
                                  double anchor_stiffness, double fat_thickness = 0) {
    const uint32_t v = add_vertex(x, y, z, anchor_stiffness, fat_thickness);
    anchors[v].normal_a = anchors[v].normal_b = {static_cast<int32_t>(std::llround(nx * 1073741824.0)),
                                                 static_cast<int32_t>(std::llround(ny * 1073741824.0)),
                                                 static_cast<int32_t>(std::llround(nz * 1073741824.0))};
    return v;
  }
  void add_triangle(uint32_t a, uint32_t b, uint32_t c) { triangles.insert(triangles.end(), {a, b, c}); }
  void add_edge(uint32_t a, uint32_t b, double k, double rest) {
    edges.push_back({a, b, to_len(rest), static_cast<elastic_skin::Stiffness>(to_q16(k))});
  }
  // Band to ring vertex j of slice 0 of the fake muscle, at `target`.
  void add_band(uint32_t vertex, uint32_t j, double k, double tx, double ty, double tz) {
    bands.push_back({vertex, 0, 0, j, static_cast<elastic_skin::Stiffness>(to_q16(k))});
    band_target[j] = {to_len(tx), to_len(ty), to_len(tz)};
  }
  // An active sphere of `radius` at `centre` (units).
  void add_sphere(double cx, double cy, double cz, double radius) {
    muscle::PrimitiveFrame f;
    f.centre = {to_len(cx), to_len(cy), to_len(cz)};
    f.axis[0] = {fx::kUnitOne, 0, 0};
    f.axis[1] = {0, fx::kUnitOne, 0};
    f.axis[2] = {0, 0, fx::kUnitOne};
    f.extent[0] = f.extent[1] = f.extent[2] = to_len(radius);
    f.kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSphere);
    f.exponent = 2;
    f.active = 1;
    frames.push_back(f);
    primitive_records.emplace_back();
  }

  // Wires the spans and carves the state; false if init refuses.
  bool finish() {
    model.vertex_count = static_cast<uint32_t>(anchors.size());
    model.anchors = anchors;
    model.anchor_stiffness = anchor_k;
    model.fat = fat;
    model.edges = edges;
    model.bands = bands;
    model.triangles = triangles;
    muscles.joint_count = 1;
    muscles.ring_vertices = kRing;
    muscles.muscles = muscle_records;
    muscles.primitives = primitive_records;
    slice_frames.resize(muscle::kSlices);
    for (int c = 0; c < 3; ++c) ring[c].assign(muscle::kSlices * kRing, 0);
    for (uint32_t j = 0; j < kRing; ++j) {
      ring[0][j] = band_target[j].x;
      ring[1][j] = band_target[j].y;
      ring[2][j] = band_target[j].z;
    }
    mstate.ring_vertices = kRing;
    mstate.frames = slice_frames;
    for (int c = 0; c < 3; ++c) mstate.vertex[c] = ring[c];
    mstate.primitives = frames;
    memory.assign(elastic_skin::skin_state_bytes(model) / 8 + 1, 0);
    return elastic_skin::skin_init(model, memory.data(), memory.size() * 8, &state).ok();
  }

  void move_bone(double x, double y, double z) {
    bone.t[0] = to_len(x);
    bone.t[1] = to_len(y);
    bone.t[2] = to_len(z);
  }
  muscle::LayerStatus step(uint32_t tick_hz, fx::Vec3 base_acceleration = {0, 0, 0}) {
    elastic_skin::SkinTick tick;
    tick.tick_hz = tick_hz;
    tick.base_acceleration = base_acceleration;
    tick.max_anchor_acceleration = max_anchor_acceleration;
    return elastic_skin::skin_step(model, muscles, mstate, std::span<const fx::Mat34>(&bone, 1), tick, &state);
  }
  double pos(int axis, uint32_t v) const { return from_len(state.position[axis][v]); }
  double vel(int axis, uint32_t v) const { return from_len(state.velocity[axis][v]); }

  int32_t max_anchor_acceleration = 0;  // SkinTick's cap, Q24.8 units / s^2 (0: none)
  elastic_skin::SkinModel model;
  muscle::MuscleModel muscles;
  muscle::MuscleState mstate;
  elastic_skin::SkinState state;
  fx::Mat34 bone;

  std::vector<elastic_skin::Anchor> anchors;
  std::vector<elastic_skin::Stiffness> anchor_k;
  std::vector<fx::Len> fat;
  std::vector<elastic_skin::Edge> edges;
  std::vector<elastic_skin::RubberBand> bands;
  std::vector<uint32_t> triangles;
  std::vector<muscle::MuscleRecord> muscle_records;
  std::vector<muscle::PrimitiveRecord> primitive_records;
  std::vector<muscle::PrimitiveFrame> frames;
  std::vector<muscle::SliceFrame> slice_frames;
  std::vector<fx::Len> ring[3];
  fx::Vec3 band_target[kRing] = {};
  std::vector<uint64_t> memory;
};

}  // namespace sinew::test
