// glTF skins -> RigSpec (see gltf_import.hpp for the joint and vertex order).
#include <algorithm>
#include <cmath>
#include <set>

#include "gltf_accessor.hpp"
#include "gltf_import.hpp"
#include "sim_core/rig/rig_format.hpp"

namespace sinew::rigc {
namespace {

std::string prim_name(size_t node, size_t prim) {
  return "node " + std::to_string(node) + " primitive " + std::to_string(prim);
}

bool attribute(const tinygltf::Primitive& p, const char* name, int* accessor) {
  const auto it = p.attributes.find(name);
  if (it == p.attributes.end()) return false;
  *accessor = it->second;
  return true;
}

std::string node_name(const tinygltf::Model& m, size_t n) {
  const std::string& name = m.nodes[n].name;
  return "node " + std::to_string(n) + (name.empty() ? "" : " (" + name + ")");
}

// Truncates to what the rig's name table holds, without splitting a UTF-8 sequence.
std::string fit_name(std::string s, size_t max_bytes) {
  if (s.size() <= max_bytes) return s;
  size_t n = max_bytes;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0u) == 0x80u) --n;
  s.resize(n);
  return s;
}

// Unique, stable joint names: a node's own name when no earlier joint took it
// (after truncation to the rig's name size), "node<index>" for unnamed nodes,
// and "<name>~<index>" (then "~<index>.<k>") for the rest.
void assign_joint_names(const tinygltf::Model& m, const std::vector<int>& joint_node, std::vector<JointSpec>* joints) {
  const size_t max_bytes = rig::kNameBytes - 1;
  std::set<std::string> used;
  std::vector<bool> named(joints->size(), false);
  for (size_t j = 0; j < joints->size(); ++j) {
    const std::string& own = m.nodes[static_cast<size_t>(joint_node[j])].name;
    if (own.empty()) continue;
    const std::string name = fit_name(own, max_bytes);
    if (!used.insert(name).second) continue;
    (*joints)[j].name = name;
    named[j] = true;
  }
  for (size_t j = 0; j < joints->size(); ++j) {
    if (named[j]) continue;
    const size_t n = static_cast<size_t>(joint_node[j]);
    const std::string& own = m.nodes[n].name;
    std::string name = own.empty() ? "node" + std::to_string(n) : fit_name(own, max_bytes);
    for (size_t k = 0; !used.insert(name).second; ++k) {
      const std::string suffix = "~" + std::to_string(n) + (k == 0 ? "" : "." + std::to_string(k));
      name = fit_name(own.empty() ? "node" + std::to_string(n) : own, max_bytes - suffix.size()) + suffix;
    }
    (*joints)[j].name = name;
  }
}

// `path` names the model in messages; the model is loaded already.
bool import_model(const std::string& path, GltfRig* out, std::string* error) {
  const tinygltf::Model& m = out->model;
  const size_t node_count = m.nodes.size();
  if (!check_nodes(m, error)) return *error = path + ": " + *error, false;

  // Parents, and the skinned nodes in document order.
  std::vector<int> parent(node_count, -1);
  for (size_t i = 0; i < node_count; ++i)
    for (int c : m.nodes[i].children) {
      if (c < 0 || static_cast<size_t>(c) >= node_count)
        return *error = path + ": node child index out of range", false;
      if (static_cast<size_t>(c) == i)
        return *error = path + ": " + node_name(m, i) + " lists itself as a child", false;
      if (parent[static_cast<size_t>(c)] != -1)
        return *error = path + ": node " + std::to_string(c) + " has two parents", false;
      parent[static_cast<size_t>(c)] = static_cast<int>(i);
    }
  // Depth of every node, iteratively; a node met again on its own ancestor
  // chain is in a cycle.
  std::vector<size_t> depth(node_count, 0);  // 0: not yet known; roots have depth 1
  std::vector<bool> on_chain(node_count, false);
  std::vector<size_t> chain;
  for (size_t i = 0; i < node_count; ++i) {
    chain.clear();
    size_t a = i;
    while (depth[a] == 0) {
      if (on_chain[a])
        return *error = path + ": " + node_name(m, a) + " is its own ancestor (a cycle in the node hierarchy)", false;
      on_chain[a] = true;
      chain.push_back(a);
      if (parent[a] < 0) break;
      a = static_cast<size_t>(parent[a]);
    }
    size_t d = depth[a];  // 0 when the walk ended at a root (the last node of `chain`)
    for (size_t k = chain.size(); k-- > 0;) {
      const size_t node = chain[k];
      depth[node] = ++d;
      on_chain[node] = false;
      if (d > kMaxNodeDepth)
        return *error = path + ": " + node_name(m, node) + " is nested " + std::to_string(d) +
                        " levels deep (at most " + std::to_string(kMaxNodeDepth) + ")",
               false;
    }
  }
  std::vector<size_t> skinned;
  for (size_t i = 0; i < node_count; ++i)
    if (m.nodes[i].mesh >= 0 && m.nodes[i].skin >= 0) skinned.push_back(i);
  if (skinned.empty()) return *error = path + ": no node has both a mesh and a skin", false;

  // Rig joints: skin joints of used skins plus ancestors, parents first (DFS from roots).
  std::vector<bool> wanted(node_count, false);
  std::vector<int> skins_used;
  for (size_t n : skinned) {
    const int s = m.nodes[n].skin;
    if (static_cast<size_t>(s) >= m.skins.size())
      return *error = path + ": node " + std::to_string(n) + " skin index out of range", false;
    if (std::find(skins_used.begin(), skins_used.end(), s) == skins_used.end()) skins_used.push_back(s);
  }
  for (int s : skins_used) {
    const std::vector<int>& joints = m.skins[static_cast<size_t>(s)].joints;
    if (joints.empty()) return *error = path + ": skin " + std::to_string(s) + " has no joints", false;
    if (joints.size() > rig::kMaxPalette)
      return *error = path + ": skin " + std::to_string(s) + " has " + std::to_string(joints.size()) +
                      " joints (at most " + std::to_string(rig::kMaxPalette) + ")",
             false;
    for (int j : joints) {
      if (j < 0 || static_cast<size_t>(j) >= node_count)
        return *error = path + ": skin " + std::to_string(s) + " joint index out of range", false;
      // The hierarchy is acyclic and at most kMaxNodeDepth deep (checked above).
      for (int a = j; a >= 0 && !wanted[static_cast<size_t>(a)]; a = parent[static_cast<size_t>(a)])
        wanted[static_cast<size_t>(a)] = true;
    }
  }
  std::vector<int> node_joint(node_count, -1);
  const std::vector<NodeTrs> rest = rest_node_trs(m);
  RigSpec& spec = out->spec;
  std::vector<size_t> stack;
  for (size_t r = node_count; r-- > 0;)
    if (parent[r] == -1) stack.push_back(r);
  while (!stack.empty()) {  // preorder, children in document order
    const size_t n = stack.back();
    stack.pop_back();
    if (wanted[n]) {
      JointSpec j;
      j.parent = parent[n] >= 0 ? node_joint[static_cast<size_t>(parent[n])] : -1;
      j.translation = rest[n].translation;
      j.rotation = rest[n].rotation;
      j.scale = rest[n].scale;
      node_joint[n] = static_cast<int>(spec.joints.size());
      out->joint_node.push_back(static_cast<int>(n));
      spec.joints.push_back(j);
      if (spec.joints.size() > rig::kMaxJoints)
        return *error = path + ": more than " + std::to_string(rig::kMaxJoints) + " joints", false;
    }
    const std::vector<int>& children = m.nodes[n].children;
    for (size_t c = children.size(); c-- > 0;) stack.push_back(static_cast<size_t>(children[c]));
  }
  assign_joint_names(m, out->joint_node, &spec.joints);

  // Palette: one entry per (skin, joint).
  std::vector<int> palette_base(m.skins.size(), -1);
  for (int s : skins_used) {
    const tinygltf::Skin& skin = m.skins[static_cast<size_t>(s)];
    palette_base[static_cast<size_t>(s)] = static_cast<int>(spec.palette.size());
    std::vector<double> ibm;
    if (skin.inverseBindMatrices >= 0) {
      int comps = 0;
      if (!read_accessor(m, skin.inverseBindMatrices, rig::kMaxPalette, &ibm, &comps, error))
        return *error = path + ": skin " + std::to_string(s) + " inverseBindMatrices: " + *error, false;
      if (comps != 16 || ibm.size() < skin.joints.size() * 16)
        return *error = path + ": skin " + std::to_string(s) + " has fewer inverse bind matrices than joints", false;
    }
    for (size_t j = 0; j < skin.joints.size(); ++j) {
      PaletteSpec p;
      p.joint = node_joint[static_cast<size_t>(skin.joints[j])];
      if (!ibm.empty()) std::copy_n(ibm.begin() + static_cast<long>(j * 16), 16, p.inverse_bind.begin());
      spec.palette.push_back(p);
    }
  }

  // Vertices of every skinned primitive, in document order.
  bool all_normals = true;
  double extent = 0;
  for (size_t n : skinned) {
    const tinygltf::Node& node = m.nodes[n];
    if (static_cast<size_t>(node.mesh) >= m.meshes.size())
      return *error = path + ": node mesh index out of range", false;
    const tinygltf::Skin& skin = m.skins[static_cast<size_t>(node.skin)];
    const int base = palette_base[static_cast<size_t>(node.skin)];
    const auto& prims = m.meshes[static_cast<size_t>(node.mesh)].primitives;
    for (size_t pi = 0; pi < prims.size(); ++pi) {
      const tinygltf::Primitive& p = prims[pi];
      const std::string where = path + ": " + prim_name(n, pi);
      int acc = -1, comps = 0;
      std::vector<double> pos, nrm, joints[2], weights[2];
      if (!attribute(p, "POSITION", &acc)) return *error = where + " has no POSITION", false;
      if (!read_accessor(m, acc, rig::kMaxVertices, &pos, &comps, error))
        return *error = where + ": POSITION: " + *error, false;
      if (comps != 3) return *error = where + ": POSITION must be VEC3", false;
      const size_t count = pos.size() / 3;
      if (spec.vertices.size() + count > rig::kMaxVertices)
        return *error = where + ": more than " + std::to_string(rig::kMaxVertices) + " vertices in the rig", false;
      if (spec.primitives.size() >= rig::kMaxPrimitives)
        return *error = where + ": more than " + std::to_string(rig::kMaxPrimitives) + " skinned primitives", false;
      if (attribute(p, "NORMAL", &acc)) {
        if (!read_accessor(m, acc, rig::kMaxVertices, &nrm, &comps, error))
          return *error = where + ": NORMAL: " + *error, false;
        if (comps != 3 || nrm.size() != pos.size()) return *error = where + ": NORMAL does not match POSITION", false;
      } else {
        all_normals = false;
      }
      int sets = 0;
      for (int set = 0; set < 2; ++set) {
        int ja = -1, wa = -1;
        const bool has_j = attribute(p, set == 0 ? "JOINTS_0" : "JOINTS_1", &ja);
        const bool has_w = attribute(p, set == 0 ? "WEIGHTS_0" : "WEIGHTS_1", &wa);
        if (!has_j && !has_w) continue;
        if (has_j != has_w)
          return *error = where + ": JOINTS_" + std::to_string(set) + " and WEIGHTS_" + std::to_string(set) +
                          " must come together",
                 false;
        int cj = 0, cw = 0;
        if (!read_accessor(m, ja, rig::kMaxVertices, &joints[set], &cj, error) ||
            !read_accessor(m, wa, rig::kMaxVertices, &weights[set], &cw, error))
          return *error = where + ": " + *error, false;
        if (m.accessors[static_cast<size_t>(ja)].normalized)
          return *error = where + ": JOINTS_" + std::to_string(set) + " must not be normalized", false;
        if (cj != 4 || cw != 4 || joints[set].size() != count * 4 || weights[set].size() != count * 4)
          return *error = where + ": JOINTS/WEIGHTS accessors do not match POSITION", false;
        ++sets;
      }
      if (sets == 0) return *error = where + " has no JOINTS_0/WEIGHTS_0", false;
      int extra = -1;
      if (attribute(p, "WEIGHTS_2", &extra)) {
        std::vector<double> w2;
        if (read_accessor(m, extra, rig::kMaxVertices, &w2, &comps, error) &&
            std::any_of(w2.begin(), w2.end(), [](double w) { return w > 0; }))
          return *error = where + ": more than 8 influences per vertex (WEIGHTS_2 is used); sinew supports at most 8",
                 false;
      }
      const uint32_t first = static_cast<uint32_t>(spec.vertices.size());
      for (size_t v = 0; v < count; ++v) {
        VertexSpec vs;
        vs.position = {pos[v * 3], pos[v * 3 + 1], pos[v * 3 + 2]};
        extent = std::max({extent, std::fabs(vs.position[0]), std::fabs(vs.position[1]), std::fabs(vs.position[2])});
        if (!nrm.empty()) vs.normal = {nrm[v * 3], nrm[v * 3 + 1], nrm[v * 3 + 2]};
        for (int set = 0; set < 2; ++set) {
          if (joints[set].empty()) continue;
          for (size_t c = 0; c < 4; ++c) {
            const double w = weights[set][v * 4 + c];
            if (w < 0)
              return *error = where + ": vertex " + std::to_string(v) + " has a negative weight (" + std::to_string(w) +
                              ") in WEIGHTS_" + std::to_string(set),
                     false;
            if (!(w > 0)) continue;
            const double j = joints[set][v * 4 + c];
            if (!(j >= 0) || j != std::floor(j) || j >= static_cast<double>(skin.joints.size()))
              return *error = where + ": vertex " + std::to_string(v) + " uses joint " + std::to_string(j) +
                              " but the skin has " + std::to_string(skin.joints.size()),
                     false;
            vs.influences.push_back({base + static_cast<int>(j), w});
          }
        }
        if (vs.influences.empty())
          return *error = where + ": vertex " + std::to_string(v) + " has no non-zero weight", false;
        spec.vertices.push_back(vs);
      }
      spec.primitives.push_back({first, static_cast<uint32_t>(count)});
      if (p.mode == TINYGLTF_MODE_TRIANGLES || p.mode == -1) {
        std::vector<double> idx;
        if (p.indices >= 0) {
          const int type = accessor_component_type(m, p.indices);
          if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
              type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            return *error = where + ": indices must be unsigned integers", false;
          if (!read_accessor(m, p.indices, 3 * size_t{rig::kMaxTriangles}, &idx, &comps, error))
            return *error = where + ": indices: " + *error, false;
          if (comps != 1 || m.accessors[static_cast<size_t>(p.indices)].normalized)
            return *error = where + ": indices must be a SCALAR, not normalized", false;
        } else {
          for (size_t v = 0; v < count; ++v) idx.push_back(static_cast<double>(v));
        }
        for (size_t t = 0; t + 2 < idx.size(); t += 3) {
          std::array<uint32_t, 3> tri{};
          for (size_t c = 0; c < 3; ++c) {
            if (!(idx[t + c] >= 0) || idx[t + c] >= static_cast<double>(count))
              return *error = where + ": index beyond the vertex count", false;
            tri[c] = first + static_cast<uint32_t>(idx[t + c]);
          }
          spec.triangles.push_back(tri);
          if (spec.triangles.size() > rig::kMaxTriangles)
            return *error = where + ": more than " + std::to_string(rig::kMaxTriangles) + " triangles in the rig",
                   false;
        }
      }
    }
  }
  spec.has_normals = all_normals;

  // Animated translations must fit the chosen length unit too.
  for (size_t a = 0; a < m.animations.size(); ++a)
    for (const auto& ch : m.animations[a].channels) {
      if (ch.target_path != "translation" || ch.sampler < 0 ||
          static_cast<size_t>(ch.sampler) >= m.animations[a].samplers.size())
        continue;
      std::vector<double> out_values;
      int comps = 0;
      std::string ignored;
      if (read_accessor(m, m.animations[a].samplers[static_cast<size_t>(ch.sampler)].output, 3 * kMaxAnimationKeys,
                        &out_values, &comps, &ignored))
        for (double v : out_values) extent = std::max(extent, std::fabs(v));
    }
  spec.extra_extent = extent;
  return true;
}

}  // namespace

bool import_gltf(const std::string& path, GltfRig* out, std::string* error) {
  try {
    return load_gltf_model(path, &out->model, error) && import_model(path, out, error);
  } catch (const std::exception& e) {
    return *error = path + ": cannot import (" + e.what() + ")", false;
  }
}

bool import_gltf_from_memory(std::span<const uint8_t> bytes, const std::string& name, const std::string& base_dir,
                             GltfRig* out, std::string* error) {
  try {
    return load_gltf_model_from_memory(bytes, name, base_dir, &out->model, error) && import_model(name, out, error);
  } catch (const std::exception& e) {
    return *error = name + ": cannot import (" + e.what() + ")", false;
  }
}

}  // namespace sinew::rigc
