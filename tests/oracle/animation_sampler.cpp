#include "animation_sampler.hpp"

#include <algorithm>
#include <cmath>

#include "accessor_reader.hpp"

namespace sinew::oracle::detail {
namespace {

enum class Interpolation { linear, step, cubic_spline };

struct Keyframes {
  AccessorData times;
  AccessorData values;  // one value per key, or in-tangent/value/out-tangent triplets for CUBICSPLINE
  Interpolation interpolation = Interpolation::linear;
};

bool read_keyframes(const tinygltf::Model& model, const tinygltf::Animation& animation, int sampler_index,
                    int value_type, const std::string& what, Keyframes* keys, std::string* error) {
  if (sampler_index < 0 || static_cast<size_t>(sampler_index) >= animation.samplers.size()) {
    *error = what + ": sampler " + std::to_string(sampler_index) + " does not exist";
    return false;
  }
  const tinygltf::AnimationSampler& sampler = animation.samplers[static_cast<size_t>(sampler_index)];
  const std::string name = what + " sampler " + std::to_string(sampler_index);
  if (sampler.interpolation.empty() || sampler.interpolation == "LINEAR") {
    keys->interpolation = Interpolation::linear;
  } else if (sampler.interpolation == "STEP") {
    keys->interpolation = Interpolation::step;
  } else if (sampler.interpolation == "CUBICSPLINE") {
    keys->interpolation = Interpolation::cubic_spline;
  } else {
    *error = name + ": unknown interpolation " + sampler.interpolation;
    return false;
  }
  if (!read_accessor(model, sampler.input, TINYGLTF_TYPE_SCALAR, name + " input", &keys->times, error)) return false;
  if (keys->times.count == 0) return *error = name + ": no keyframes", false;
  for (size_t k = 0; k < keys->times.count; ++k) {
    const double t = keys->times.values[k];
    if (!std::isfinite(t) || (k > 0 && t < keys->times.values[k - 1])) {
      *error = name + ": keyframe times must be finite and increasing";
      return false;
    }
  }
  if (value_type == TINYGLTF_TYPE_SCALAR) return true;  // time range only
  if (!read_accessor(model, sampler.output, value_type, name + " output", &keys->values, error)) return false;
  const size_t per_key = keys->interpolation == Interpolation::cubic_spline ? 3 : 1;
  if (keys->values.count != per_key * keys->times.count) {
    *error = name + ": " + std::to_string(keys->values.count) + " output values for " +
             std::to_string(keys->times.count) + " keyframes (expected " + std::to_string(per_key * keys->times.count) +
             ")";
    return false;
  }
  return true;
}

// One VEC3 or VEC4 keyframe value; a VEC3 leaves the fourth component 0.
Eigen::Vector4d element(const AccessorData& data, size_t index) {
  Eigen::Vector4d v = Eigen::Vector4d::Zero();
  for (int c = 0; c < data.components; ++c) v[c] = data.at(index, c);
  return v;
}

// Spherical linear interpolation of unit quaternions along the shorter arc.
// The angle comes from atan2 of chord lengths, accurate even for tiny angles.
Eigen::Vector4d slerp(Eigen::Vector4d a, Eigen::Vector4d b, double u) {
  a.normalize();
  b.normalize();
  if (a.dot(b) < 0) b = -b;
  const double theta = 2.0 * std::atan2((a - b).norm(), (a + b).norm());
  const double sin_theta = std::sin(theta);
  if (sin_theta == 0.0) return a;
  return (std::sin((1.0 - u) * theta) / sin_theta) * a + (std::sin(u * theta) / sin_theta) * b;
}

Eigen::Vector4d sample(const Keyframes& keys, bool is_rotation, double time) {
  const std::vector<double>& times = keys.times.values;
  const bool cubic = keys.interpolation == Interpolation::cubic_spline;
  const auto value = [&](size_t key) { return element(keys.values, cubic ? 3 * key + 1 : key); };
  if (time <= times.front()) return value(0);
  if (time >= times.back()) return value(times.size() - 1);
  // Last key at or before `time`; the next one is strictly later, so dt > 0.
  const size_t k = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), time) - times.begin()) - 1;
  const double dt = times[k + 1] - times[k];
  const double u = (time - times[k]) / dt;
  switch (keys.interpolation) {
    case Interpolation::step:
      return value(k);
    case Interpolation::linear:
      if (is_rotation) return slerp(value(k), value(k + 1), u);
      return (1.0 - u) * value(k) + u * value(k + 1);
    case Interpolation::cubic_spline: {
      const Eigen::Vector4d out_tangent = element(keys.values, 3 * k + 2);
      const Eigen::Vector4d in_tangent = element(keys.values, 3 * (k + 1));
      const double u2 = u * u, u3 = u2 * u;
      return (2 * u3 - 3 * u2 + 1) * value(k) + (u3 - 2 * u2 + u) * dt * out_tangent +
             (-2 * u3 + 3 * u2) * value(k + 1) + (u3 - u2) * dt * in_tangent;
    }
  }
  return value(k);
}

bool find_animation(const tinygltf::Model& model, int animation, std::string* error) {
  if (animation < 0 || static_cast<size_t>(animation) >= model.animations.size()) {
    *error = "animation " + std::to_string(animation) + " out of range (the file has " +
             std::to_string(model.animations.size()) + " animations)";
    return false;
  }
  return true;
}

}  // namespace

bool apply_animation(const tinygltf::Model& model, int animation, double time, NodePoses* poses, std::string* error) {
  if (!find_animation(model, animation, error)) return false;
  if (!std::isfinite(time)) return *error = "animation time is not finite", false;
  const tinygltf::Animation& anim = model.animations[static_cast<size_t>(animation)];
  for (size_t c = 0; c < anim.channels.size(); ++c) {
    const tinygltf::AnimationChannel& channel = anim.channels[c];
    const std::string& path = channel.target_path;
    if (channel.target_node < 0 || (path != "translation" && path != "rotation" && path != "scale")) continue;
    const std::string what = "animation " + std::to_string(animation) + " channel " + std::to_string(c);
    if (static_cast<size_t>(channel.target_node) >= poses->size()) {
      *error = what + ": target node " + std::to_string(channel.target_node) + " does not exist";
      return false;
    }
    NodePose& pose = (*poses)[static_cast<size_t>(channel.target_node)];
    if (pose.has_matrix) {
      *error = what + ": targets node " + std::to_string(channel.target_node) +
               ", which has a matrix (glTF allows animating TRS nodes only)";
      return false;
    }
    const bool is_rotation = path == "rotation";
    Keyframes keys;
    if (!read_keyframes(model, anim, channel.sampler, is_rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, what,
                        &keys, error))
      return false;
    const Eigen::Vector4d v = sample(keys, is_rotation, time);
    if (!v.allFinite()) return *error = what + ": sampled value is not finite", false;
    if (path == "translation") {
      pose.translation = v.head<3>();
    } else if (path == "scale") {
      pose.scale = v.head<3>();
    } else {
      if (!(v.norm() > 0)) return *error = what + ": sampled rotation is a zero quaternion", false;
      pose.rotation = v.normalized();  // CUBICSPLINE and quantised outputs are not unit: the spec normalises
    }
  }
  return true;
}

bool animation_range(const tinygltf::Model& model, int animation, double* start, double* end, std::string* error) {
  if (!find_animation(model, animation, error)) return false;
  const tinygltf::Animation& anim = model.animations[static_cast<size_t>(animation)];
  if (anim.samplers.empty()) return *error = "animation " + std::to_string(animation) + " has no samplers", false;
  for (size_t s = 0; s < anim.samplers.size(); ++s) {
    Keyframes keys;
    if (!read_keyframes(model, anim, static_cast<int>(s), TINYGLTF_TYPE_SCALAR,
                        "animation " + std::to_string(animation), &keys, error))
      return false;
    *start = s == 0 ? keys.times.values.front() : std::min(*start, keys.times.values.front());
    *end = s == 0 ? keys.times.values.back() : std::max(*end, keys.times.values.back());
  }
  return true;
}

}  // namespace sinew::oracle::detail
