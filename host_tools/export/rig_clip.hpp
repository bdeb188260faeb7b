// Fills a SurfaceClip from sim_core's fixed-point data: the rig's rest
// surface and skeleton, and frames of skinned positions (Q12.20 rig units),
// normals (Q2.30) and joint local transforms. One rig unit is
// 2^length_exponent metres (docs/rig-format.md), so x metres = q * 2^(e - 20).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sim_core/rig/rig.hpp"
#include "sim_core/skeleton/pose.hpp"
#include "surface_clip.hpp"

namespace sinew::gltf_export {

// One frame of the deformed surface as sim_core computes it.
struct FixedFrame {
  std::span<const int32_t> position[3];  // Q12.20 rig units, V each
  std::span<const int32_t> normal[3];    // Q2.30, V each; empty: derived from the triangles
};

// The rest surface (positions, normals: the rig's or derived), triangles,
// joints (names from the rig, "joint<j>" without them) and rest skeleton.
void set_rest_from_rig(const rig::Rig& rig, SurfaceClip* clip);

JointTransform joint_transform(const skeleton::LocalPose& local, int32_t length_exponent);

// Appends a frame at time_s. frame's spans hold rig.vertex_count() values;
// locals one per joint.
void append_frame(const rig::Rig& rig, double time_s, const FixedFrame& frame,
                  std::span<const skeleton::LocalPose> locals, SurfaceClip* clip);

// Area-weighted vertex normals of a triangle mesh (positions xyz
// interleaved); a vertex on no triangle of non-zero area gets +z.
void vertex_normals(std::span<const float> position, std::span<const uint32_t> triangles, std::vector<float>* normal);

}  // namespace sinew::gltf_export
