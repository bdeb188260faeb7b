#include "clip_glb.hpp"

#include <cmath>
#include <cstdio>
#include <exception>

#include "glb_writer.hpp"

namespace sinew::gltf_export {
namespace {

using nlohmann::json;

bool scale_is_one(const JointTransform& t) { return t.scale[0] == 1.0f && t.scale[1] == 1.0f && t.scale[2] == 1.0f; }

json node_of_joint(const ClipJoint& joint, const JointTransform& rest) {
  json node = {{"name", joint.name},
               {"translation", {rest.translation[0], rest.translation[1], rest.translation[2]}},
               {"rotation", {rest.rotation[0], rest.rotation[1], rest.rotation[2], rest.rotation[3]}}};
  if (!scale_is_one(rest)) node["scale"] = {rest.scale[0], rest.scale[1], rest.scale[2]};
  return node;
}

// Offsets of one frame from the rest surface (a morph target's data).
std::vector<float> deltas(const std::vector<float>& frame, const std::vector<float>& rest) {
  std::vector<float> d(rest.size());
  for (size_t i = 0; i < rest.size(); ++i) d[i] = frame[i] - rest[i];
  return d;
}

std::string frame_name(const ClipFrame& frame, size_t k) {
  char name[64];
  std::snprintf(name, sizeof(name), "frame %zu t=%.6f s", k, frame.time_s);
  return name;
}

void add_animation(const SurfaceClip& clip, GlbBuilder* glb) {
  const size_t n = clip.frames.size(), joints = clip.joints.size();
  std::vector<float> times(n);
  for (size_t k = 0; k < n; ++k) times[k] = static_cast<float>(clip.frames[k].time_s);
  const int input = glb->add_float_accessor(times, "SCALAR", true, 0);  // inputs need min/max (§3.11)
  json samplers = json::array(), channels = json::array();
  auto add_sampler = [&](const std::vector<float>& values, const char* type, int node, const char* path) {
    const int output = glb->add_float_accessor(values, type, false, 0);
    samplers.push_back({{"input", input}, {"output", output}, {"interpolation", "LINEAR"}});
    channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  };
  // Frame k's key is e_k: weight 1 on its own target, 0 on the others.
  std::vector<float> weights(n * n, 0.0f);
  for (size_t k = 0; k < n; ++k) weights[k * n + k] = 1.0f;
  add_sampler(weights, "SCALAR", 0, "weights");
  for (size_t j = 0; j < joints; ++j) {
    std::vector<float> translation(3 * n), rotation(4 * n);
    for (size_t k = 0; k < n; ++k) {
      const JointTransform& t = clip.frames[k].joints[j];
      float sign = 1.0f;
      if (k > 0) {
        float dot = 0;
        for (size_t c = 0; c < 4; ++c) dot += t.rotation[c] * rotation[4 * (k - 1) + c];
        if (dot < 0) sign = -1.0f;  // q and -q are one rotation: keep the keys on one hemisphere
      }
      for (size_t c = 0; c < 3; ++c) translation[3 * k + c] = t.translation[c];
      for (size_t c = 0; c < 4; ++c) rotation[4 * k + c] = sign * t.rotation[c];
    }
    add_sampler(translation, "VEC3", static_cast<int>(j) + 1, "translation");
    add_sampler(rotation, "VEC4", static_cast<int>(j) + 1, "rotation");
  }
  glb->document()["animations"] = json::array({{{"name", "run"}, {"samplers", samplers}, {"channels", channels}}});
}

}  // namespace

std::string check_clip(const SurfaceClip& clip) {
  const size_t v = clip.vertex_count();
  if (v == 0 || clip.rest_position.size() != 3 * v) return "the surface has no vertices";
  if (clip.rest_normal.size() != 3 * v) return "the rest normals do not match the vertex count";
  if (clip.triangles.empty() || clip.triangles.size() % 3 != 0) return "the surface has no triangles";
  for (uint32_t i : clip.triangles)
    if (i >= v) return "triangle index " + std::to_string(i) + " is not below the vertex count " + std::to_string(v);
  if (clip.frames.empty()) return "no frames to export";
  if (clip.rest_joints.size() != clip.joints.size()) return "the rest skeleton does not match the joint count";
  for (size_t j = 0; j < clip.joints.size(); ++j)
    if (clip.joints[j].parent >= static_cast<int32_t>(j) || clip.joints[j].parent < -1)
      return "joint " + std::to_string(j) + " has parent " + std::to_string(clip.joints[j].parent) +
             ", not an earlier joint";
  float last_time = 0;
  for (size_t k = 0; k < clip.frames.size(); ++k) {
    const ClipFrame& f = clip.frames[k];
    if (f.position.size() != 3 * v || f.normal.size() != 3 * v || f.joints.size() != clip.joints.size())
      return frame_name(f, k) + ": its sizes do not match the surface and skeleton";
    const float t = static_cast<float>(f.time_s);
    if (!std::isfinite(f.time_s) || t < 0 || (k > 0 && !(t > last_time)))
      return frame_name(f, k) + ": frame times must be finite, from 0, and increase strictly (as floats)";
    last_time = t;
  }
  return "";
}

bool encode_clip_glb(const SurfaceClip& clip, std::vector<uint8_t>* out, std::string* error) {
  if (const std::string why = check_clip(clip); !why.empty()) return *error = why, false;
  try {
    GlbBuilder glb(clip.generator);
    json& doc = glb.document();
    const int position = glb.add_float_accessor(clip.rest_position, "VEC3", true, kTargetArrayBuffer);
    const int normal = glb.add_float_accessor(clip.rest_normal, "VEC3", false, kTargetArrayBuffer);
    const int indices = glb.add_index_accessor(clip.triangles);
    json targets = json::array(), target_names = json::array(), weights = json::array();
    for (size_t k = 0; k < clip.frames.size(); ++k) {
      const ClipFrame& f = clip.frames[k];
      // Morph target POSITION accessors need min/max too (§3.7.2.2).
      const int dp = glb.add_float_accessor(deltas(f.position, clip.rest_position), "VEC3", true, kTargetArrayBuffer);
      const int dn = glb.add_float_accessor(deltas(f.normal, clip.rest_normal), "VEC3", false, kTargetArrayBuffer);
      targets.push_back({{"POSITION", dp}, {"NORMAL", dn}});
      target_names.push_back(frame_name(f, k));
      weights.push_back(k == 0 ? 1.0 : 0.0);  // a viewer that does not play shows the first frame
    }
    json primitive = {{"attributes", {{"POSITION", position}, {"NORMAL", normal}}},
                      {"indices", indices},
                      {"mode", 4},
                      {"targets", targets}};
    // extras.targetNames: the names Blender and three.js give the morph targets.
    doc["meshes"] = json::array({{{"name", "surface"},
                                  {"primitives", json::array({primitive})},
                                  {"weights", weights},
                                  {"extras", {{"targetNames", target_names}}}}});
    json nodes = json::array({{{"name", "surface"}, {"mesh", 0}}});
    json scene_nodes = json::array({0});
    for (size_t j = 0; j < clip.joints.size(); ++j) {
      nodes.push_back(node_of_joint(clip.joints[j], clip.rest_joints[j]));
      const int32_t parent = clip.joints[j].parent;
      if (parent < 0)
        scene_nodes.push_back(j + 1);
      else
        nodes[static_cast<size_t>(parent) + 1]["children"].push_back(j + 1);
    }
    doc["nodes"] = nodes;
    doc["scenes"] = json::array({{{"name", "run"}, {"nodes", scene_nodes}}});
    doc["scene"] = 0;
    add_animation(clip, &glb);
    json notes = json::object();
    for (const auto& [key, value] : clip.notes) notes[key] = value;
    doc["extras"] = {{"sinew", notes}};
    *out = glb.finish();
  } catch (const std::exception& e) {
    return *error = std::string("glTF encoding: ") + e.what(), false;
  }
  return true;
}

}  // namespace sinew::gltf_export
