#include "rig_clip.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "sim_core/fixed/q_formats.hpp"

namespace sinew::gltf_export {
namespace {

float len_metres(int32_t q, int32_t length_exponent) {
  return static_cast<float>(std::ldexp(static_cast<double>(q), length_exponent - fx::kLenFracBits));
}

// Unit vectors stored as floats must read back as unit within the
// validator's tolerance, so normalise in double first.
void put_unit(double x, double y, double z, float* out) {
  const double n = std::sqrt(x * x + y * y + z * z);
  if (!(n > 0)) {
    out[0] = 0, out[1] = 0, out[2] = 1;
    return;
  }
  out[0] = static_cast<float>(x / n), out[1] = static_cast<float>(y / n), out[2] = static_cast<float>(z / n);
}

void surface_from_fixed(const rig::Rig& rig, const FixedFrame& frame, std::vector<float>* position,
                        std::vector<float>* normal) {
  const uint32_t v = rig.vertex_count();
  position->resize(3 * size_t{v});
  for (uint32_t i = 0; i < v; ++i)
    for (int c = 0; c < 3; ++c)
      (*position)[3 * size_t{i} + static_cast<size_t>(c)] = len_metres(frame.position[c][i], rig.length_exponent);
  if (frame.normal[0].size() < v || frame.normal[1].size() < v || frame.normal[2].size() < v) {
    vertex_normals(*position, rig.triangles, normal);
    return;
  }
  normal->resize(3 * size_t{v});
  for (uint32_t i = 0; i < v; ++i)
    put_unit(static_cast<double>(frame.normal[0][i]), static_cast<double>(frame.normal[1][i]),
             static_cast<double>(frame.normal[2][i]), normal->data() + 3 * size_t{i});
}

}  // namespace

void vertex_normals(std::span<const float> position, std::span<const uint32_t> triangles, std::vector<float>* normal) {
  const size_t v = position.size() / 3;
  std::vector<double> sum(3 * v, 0.0);
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const size_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    if (a >= v || b >= v || c >= v) continue;
    double e1[3], e2[3];
    for (size_t k = 0; k < 3; ++k) {
      e1[k] = double{position[3 * b + k]} - double{position[3 * a + k]};
      e2[k] = double{position[3 * c + k]} - double{position[3 * a + k]};
    }
    // The cross product's length is twice the triangle's area: area weighting.
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (const size_t corner : {a, b, c})
      for (size_t k = 0; k < 3; ++k) sum[3 * corner + k] += n[k];
  }
  normal->resize(3 * v);
  for (size_t i = 0; i < v; ++i) put_unit(sum[3 * i], sum[3 * i + 1], sum[3 * i + 2], normal->data() + 3 * i);
}

JointTransform joint_transform(const skeleton::LocalPose& local, int32_t length_exponent) {
  JointTransform t;
  t.translation[0] = len_metres(local.translation.x, length_exponent);
  t.translation[1] = len_metres(local.translation.y, length_exponent);
  t.translation[2] = len_metres(local.translation.z, length_exponent);
  const double q[4] = {static_cast<double>(local.rotation.x), static_cast<double>(local.rotation.y),
                       static_cast<double>(local.rotation.z), static_cast<double>(local.rotation.w)};
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (size_t c = 0; c < 4; ++c) t.rotation[c] = n > 0 ? static_cast<float>(q[c] / n) : (c == 3 ? 1.0f : 0.0f);
  const int32_t s[3] = {local.scale.x, local.scale.y, local.scale.z};
  for (size_t c = 0; c < 3; ++c)
    t.scale[c] = static_cast<float>(std::ldexp(static_cast<double>(s[c]), -fx::kLinFracBits));
  return t;
}

void set_rest_from_rig(const rig::Rig& rig, SurfaceClip* clip) {
  FixedFrame rest;
  for (int c = 0; c < 3; ++c) {
    rest.position[c] = rig.position[c];
    rest.normal[c] = rig.normal[c];
  }
  surface_from_fixed(rig, rest, &clip->rest_position, &clip->rest_normal);
  clip->triangles.assign(rig.triangles.begin(), rig.triangles.end());
  std::vector<skeleton::LocalPose> locals(rig.joint_count());
  skeleton::rest_locals(rig, locals);
  clip->joints.clear();
  clip->rest_joints.clear();
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    ClipJoint joint;
    joint.parent = rig.joints[j].parent;
    if (j < rig.names.size()) joint.name.assign(rig.names[j], strnlen(rig.names[j], rig::kNameBytes));
    if (joint.name.empty()) joint.name = "joint" + std::to_string(j);
    clip->joints.push_back(joint);
    clip->rest_joints.push_back(joint_transform(locals[j], rig.length_exponent));
  }
}

void append_frame(const rig::Rig& rig, double time_s, const FixedFrame& frame,
                  std::span<const skeleton::LocalPose> locals, SurfaceClip* clip) {
  ClipFrame f;
  f.time_s = time_s;
  surface_from_fixed(rig, frame, &f.position, &f.normal);
  f.joints.reserve(locals.size());
  for (const skeleton::LocalPose& l : locals) f.joints.push_back(joint_transform(l, rig.length_exponent));
  clip->frames.push_back(std::move(f));
}

}  // namespace sinew::gltf_export
