// Encodes a SurfaceClip as a glTF 2.0 binary:
//  - one mesh, one triangle primitive: the rest surface (POSITION with
//    min/max, NORMAL, UNSIGNED_INT indices) and one morph target per frame
//    holding that frame's offsets from the rest surface (POSITION and NORMAL
//    deltas; glTF 2.0 §3.7.2.2: rendered = rest + sum(w_k * target_k));
//  - one animation whose "weights" channel keys frame k with the one-hot
//    weight vector e_k at its time, LINEAR, so between two frames the surface
//    moves linearly from one to the next; the same animation carries
//    translation and rotation channels (LINEAR; rotations kept on one
//    hemisphere so slerp takes the short way) for one node per joint;
//  - one scene: the surface node and the skeleton's root joints.
// Bytes per frame: 24 V (position and normal deltas) + 4 N (its weight key)
// + 28 J (joint keys) + 4 (its time), with V vertices, N frames, J joints.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "surface_clip.hpp"

namespace sinew::gltf_export {

// Names what is wrong with a clip (sizes, indices, times), or "" when it can
// be encoded.
std::string check_clip(const SurfaceClip& clip);

// The GLB bytes; false with the reason in *error (check_clip's message, or a
// file larger than a GLB header can state).
bool encode_clip_glb(const SurfaceClip& clip, std::vector<uint8_t>* out, std::string* error);

}  // namespace sinew::gltf_export
