// glTF 2.0 skins -> RigSpec, and glTF animations sampled into local poses.
// Rig joints are every node that is a joint of a used skin, plus their
// ancestors, in parents-first order; the palette is each skin's (joint,
// inverse bind) list; vertices of every skinned primitive are concatenated in
// glTF document order (nodes order, then primitives order).
#pragma once

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

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

bool load_gltf_model(const std::string& path, tinygltf::Model* model, std::string* error);
bool import_gltf(const std::string& path, GltfRig* out, std::string* error);

// Default TRS of every node (matrix nodes decomposed).
std::vector<NodeTrs> rest_node_trs(const tinygltf::Model& model);

// Samples animation `index` at `time` (clamped to each sampler's range) over
// `trs` (start from rest_node_trs): LINEAR (slerp for rotations), STEP and
// CUBICSPLINE, as the glTF 2.0 specification defines them.
bool sample_animation(const tinygltf::Model& model, int index, double time, std::vector<NodeTrs>* trs,
                      std::string* error);

bool animation_range(const tinygltf::Model& model, int index, double* start, double* end, std::string* error);

}  // namespace sinew::rigc
