// glTF 2.0 skins -> RigSpec, and glTF animations sampled into local poses.
// Rig joints are every node that is a joint of a used skin, plus their
// ancestors, in parents-first order; the palette is each skin's (joint,
// inverse bind) list; vertices of every skinned primitive are concatenated in
// glTF document order (nodes order, then primitives order).
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "rig_spec.hpp"

namespace sinew::rigc {

struct NodeTrs {
  Vec3d translation{0, 0, 0};
  Quatd rotation{1, 0, 0, 0};
  Vec3d scale{1, 1, 1};
};

struct GltfRig {
  tinygltf::Model model;
  RigSpec spec;
  std::vector<int> joint_node;  // rig joint -> glTF node
};

// Limits checked before anything is allocated: a rig's vertex attributes,
// indices and inverse bind matrices by sim_core/rig/rig_format.hpp; animation
// keys per sampler by this importer.
inline constexpr size_t kMaxAnimationKeys = size_t{1} << 22;
// Deepest node hierarchy accepted (every ancestor of a joint is a rig joint).
inline constexpr size_t kMaxNodeDepth = 1024;

// Loads a .gltf or .glb (regular files only; images are ignored, not decoded).
// Never throws: every failure is a message naming the file.
bool load_gltf_model(const std::string& path, tinygltf::Model* model, std::string* error);
// The same from bytes in memory (a .glb when they start with the magic
// "glTF", else a .gltf); `name` names them in messages. Buffers the document
// names by relative URI are read from `base_dir`; with an empty base_dir
// none is read (only data: URIs and the .glb's own buffer are used).
bool load_gltf_model_from_memory(std::span<const uint8_t> bytes, const std::string& name, const std::string& base_dir,
                                 tinygltf::Model* model, std::string* error);
// Loads and converts; never throws. Refuses non-finite data, node cycles,
// hierarchies deeper than kMaxNodeDepth and negative weights.
bool import_gltf(const std::string& path, GltfRig* out, std::string* error);
// The same from bytes in memory (see load_gltf_model_from_memory).
bool import_gltf_from_memory(std::span<const uint8_t> bytes, const std::string& name, const std::string& base_dir,
                             GltfRig* out, std::string* error);

// Every node's matrix/TRS is finite (and a matrix decomposes into finite TRS).
bool check_nodes(const tinygltf::Model& model, std::string* error);

// Default TRS of every node (matrix nodes decomposed).
std::vector<NodeTrs> rest_node_trs(const tinygltf::Model& model);

// Samples animation `index` at `time` (clamped to each sampler's range) over
// `trs` (start from rest_node_trs); `time` must be finite. LINEAR (slerp for rotations), STEP and
// CUBICSPLINE, as the glTF 2.0 specification defines them.
bool sample_animation(const tinygltf::Model& model, int index, double time, std::vector<NodeTrs>* trs,
                      std::string* error);

bool animation_range(const tinygltf::Model& model, int index, double* start, double* end, std::string* error);

}  // namespace sinew::rigc
