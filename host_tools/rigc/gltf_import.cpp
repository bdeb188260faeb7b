#include "gltf_import.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "gltf_accessor.hpp"

namespace sinew::rigc {
namespace {

Quatd normalized(Quatd q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(n > 0)) return {1, 0, 0, 0};
  return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

// Decomposes a column-major TRS matrix (glTF forbids shear in node matrices).
NodeTrs decompose(const std::vector<double>& m) {
  NodeTrs t;
  t.translation = {m[12], m[13], m[14]};
  double col[3][3];
  for (int c = 0; c < 3; ++c) {
    const double sx = std::sqrt(m[static_cast<size_t>(c * 4)] * m[static_cast<size_t>(c * 4)] +
                                m[static_cast<size_t>(c * 4 + 1)] * m[static_cast<size_t>(c * 4 + 1)] +
                                m[static_cast<size_t>(c * 4 + 2)] * m[static_cast<size_t>(c * 4 + 2)]);
    t.scale[static_cast<size_t>(c)] = sx;
    for (int r = 0; r < 3; ++r) col[c][r] = sx > 0 ? m[static_cast<size_t>(c * 4 + r)] / sx : (r == c ? 1 : 0);
  }
  const double det = col[0][0] * (col[1][1] * col[2][2] - col[2][1] * col[1][2]) -
                     col[1][0] * (col[0][1] * col[2][2] - col[2][1] * col[0][2]) +
                     col[2][0] * (col[0][1] * col[1][2] - col[1][1] * col[0][2]);
  if (det < 0) {  // a mirror: carry it in the scale
    t.scale[0] = -t.scale[0];
    for (int r = 0; r < 3; ++r) col[0][r] = -col[0][r];
  }
  // Rotation matrix R[r][c] = col[c][r] -> quaternion (Shepperd).
  const double r00 = col[0][0], r11 = col[1][1], r22 = col[2][2];
  const double r01 = col[1][0], r10 = col[0][1], r02 = col[2][0], r20 = col[0][2], r12 = col[2][1], r21 = col[1][2];
  const double tr = r00 + r11 + r22;
  Quatd q;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    q = {0.25 * s, (r21 - r12) / s, (r02 - r20) / s, (r10 - r01) / s};
  } else if (r00 > r11 && r00 > r22) {
    const double s = std::sqrt(1.0 + r00 - r11 - r22) * 2;
    q = {(r21 - r12) / s, 0.25 * s, (r01 + r10) / s, (r02 + r20) / s};
  } else if (r11 > r22) {
    const double s = std::sqrt(1.0 + r11 - r00 - r22) * 2;
    q = {(r02 - r20) / s, (r01 + r10) / s, 0.25 * s, (r12 + r21) / s};
  } else {
    const double s = std::sqrt(1.0 + r22 - r00 - r11) * 2;
    q = {(r10 - r01) / s, (r02 + r20) / s, (r12 + r21) / s, 0.25 * s};
  }
  t.rotation = normalized(q);
  return t;
}

Quatd slerp(Quatd a, Quatd b, double u) {
  // glTF requires unit rotation keys; exporters round them (SimpleSkin's are
  // off by 5e-4), so normalise before interpolating.
  a = normalized(a);
  b = normalized(b);
  double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  if (d < 0) {  // shorter arc (glTF spec)
    d = -d;
    for (double& c : b) c = -c;
  }
  // Half-angle from atan2(|a - b|, |a + b|): accurate at every angle, unlike
  // acos(d) near 1. A lerp shortcut for close keys would err by ~1e-5.
  double diff = 0, sum = 0;
  for (size_t i = 0; i < 4; ++i) {
    diff += (a[i] - b[i]) * (a[i] - b[i]);
    sum += (a[i] + b[i]) * (a[i] + b[i]);
  }
  const double theta = 2 * std::atan2(std::sqrt(diff), std::sqrt(sum));
  double wa = 1 - u, wb = u;
  if (theta > 1e-12) {
    const double s = std::sin(theta);
    wa = std::sin((1 - u) * theta) / s;
    wb = std::sin(u * theta) / s;
  }
  return normalized({wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2], wa * a[3] + wb * b[3]});
}

// tinygltf's image callback: accepts every image without decoding it.
bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

// File-system callbacks for a document given as bytes alone: every buffer or
// image it names by URI is refused, so nothing outside the bytes is read
// (data: URIs are decoded without them). Every file "exists" so that the
// refusal reaches the read callback, whose message says why.
bool any_file_exists(const std::string&, void*) { return true; }
std::string no_expand(const std::string& path, void*) { return path; }
bool no_read(std::vector<unsigned char>*, std::string* err, const std::string&, void*) {
  if (err != nullptr) *err = "not read: the document was given as bytes, without a directory";
  return false;
}
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err != nullptr) *err = "not written";
  return false;
}
const tinygltf::FsCallbacks kNoFiles{any_file_exists, no_expand, no_read, no_write, nullptr};

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// Animation key times: finite (read_accessor) and never decreasing.
bool read_key_times(const tinygltf::Model& model, int anim, int accessor, std::vector<double>* in, std::string* error) {
  int comps = 0;
  if (!read_accessor(model, accessor, kMaxAnimationKeys, in, &comps, error))
    return *error = "animation " + std::to_string(anim) + ": " + *error, false;
  if (comps != 1)
    return *error = "animation " + std::to_string(anim) + ": accessor " + std::to_string(accessor) +
                    ": sampler input must be SCALAR",
           false;
  for (size_t k = 1; k < in->size(); ++k)
    if ((*in)[k] < (*in)[k - 1])
      return *error = "animation " + std::to_string(anim) + ": accessor " + std::to_string(accessor) +
                      ": key times decrease at key " + std::to_string(k),
             false;
  return true;
}

}  // namespace

bool load_gltf_model(const std::string& path, tinygltf::Model* model, std::string* error) {
  try {
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st)) return *error = path + ": no such file", false;
    if (!std::filesystem::is_regular_file(st)) return *error = path + ": not a regular file", false;
    std::ifstream f(path, std::ios::binary);
    if (!f) return *error = path + ": cannot open", false;
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    if (f.bad()) return *error = path + ": cannot read", false;
    // Buffers the document names by relative URI sit beside it.
    std::string base_dir = std::filesystem::path(path).parent_path().string();
    if (base_dir.empty()) base_dir = ".";
    return load_gltf_model_from_memory(bytes, path, base_dir, model, error);
  } catch (const std::exception& e) {
    return *error = path + ": not a valid glTF file (" + e.what() + ")", false;
  }
}

bool load_gltf_model_from_memory(std::span<const uint8_t> bytes, const std::string& name, const std::string& base_dir,
                                 tinygltf::Model* model, std::string* error) {
  try {
    // tinygltf takes 32-bit lengths.
    if (bytes.size() > UINT32_MAX) return *error = name + ": larger than 4 GiB", false;
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    tinygltf::TinyGLTF loader;
    // Images are never decoded: sinew reads geometry, skins and animations.
    // Without a loader tinygltf refuses every file that embeds an image.
    loader.SetImageLoader(ignore_image, nullptr);
    if (base_dir.empty()) loader.SetFsCallbacks(kNoFiles);
    std::string err, warn;
    const auto length = static_cast<unsigned int>(bytes.size());
    const bool ok = binary ? loader.LoadBinaryFromMemory(model, &err, &warn, bytes.data(), length, base_dir)
                           : loader.LoadASCIIFromString(model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                                        length, base_dir);
    if (!ok) return *error = name + ": " + (err.empty() ? "not a valid glTF file" : trimmed(err)), false;
    for (const std::string& ext : model->extensionsRequired)
      if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression")
        return *error = name + ": requires " + ext + " (compressed geometry is not supported)", false;
    return true;
  } catch (const std::exception& e) {
    return *error = name + ": not a valid glTF file (" + e.what() + ")", false;
  }
}

bool check_nodes(const tinygltf::Model& model, std::string* error) {
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    const tinygltf::Node& n = model.nodes[i];
    const std::string what = "node " + std::to_string(i) + (n.name.empty() ? "" : " (" + n.name + ")");
    if (!n.matrix.empty() && n.matrix.size() != 16) return *error = what + ": matrix needs 16 numbers", false;
    if ((!n.translation.empty() && n.translation.size() != 3) || (!n.rotation.empty() && n.rotation.size() != 4) ||
        (!n.scale.empty() && n.scale.size() != 3))
      return *error = what + ": translation and scale need 3 numbers, rotation 4", false;
    if (!finite(n.matrix) || !finite(n.translation) || !finite(n.rotation) || !finite(n.scale))
      return *error = what + ": matrix, translation, rotation or scale is not finite", false;
    if (n.matrix.size() == 16) {
      const NodeTrs t = decompose(n.matrix);
      for (size_t c = 0; c < 3; ++c)
        if (!std::isfinite(t.translation[c]) || !std::isfinite(t.scale[c]))
          return *error = what + ": matrix does not decompose into finite TRS", false;
      for (double q : t.rotation)
        if (!std::isfinite(q)) return *error = what + ": matrix does not decompose into finite TRS", false;
    }
  }
  return true;
}

std::vector<NodeTrs> rest_node_trs(const tinygltf::Model& model) {
  std::vector<NodeTrs> out(model.nodes.size());
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    const tinygltf::Node& n = model.nodes[i];
    if (n.matrix.size() == 16) {
      out[i] = decompose(n.matrix);
      continue;
    }
    if (n.translation.size() == 3) out[i].translation = {n.translation[0], n.translation[1], n.translation[2]};
    if (n.rotation.size() == 4)
      out[i].rotation = normalized({n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]});
    if (n.scale.size() == 3) out[i].scale = {n.scale[0], n.scale[1], n.scale[2]};
  }
  return out;
}

bool animation_range(const tinygltf::Model& model, int index, double* start, double* end, std::string* error) {
  if (index < 0 || static_cast<size_t>(index) >= model.animations.size())
    return *error = "animation " + std::to_string(index) + ": no such animation (the file has " +
                    std::to_string(model.animations.size()) + ")",
           false;
  *start = 1e300;
  *end = -1e300;
  for (const tinygltf::AnimationSampler& s : model.animations[static_cast<size_t>(index)].samplers) {
    std::vector<double> in;
    if (!read_key_times(model, index, s.input, &in, error)) return false;
    if (in.empty()) continue;
    *start = std::min(*start, in.front());
    *end = std::max(*end, in.back());
  }
  if (*start > *end) *start = *end = 0;
  return true;
}

bool sample_animation(const tinygltf::Model& model, int index, double time, std::vector<NodeTrs>* trs,
                      std::string* error) {
  if (index < 0 || static_cast<size_t>(index) >= model.animations.size())
    return *error = "animation " + std::to_string(index) + ": no such animation (the file has " +
                    std::to_string(model.animations.size()) + ")",
           false;
  if (!std::isfinite(time)) return *error = "animation time " + std::to_string(time) + " is not finite", false;
  const tinygltf::Animation& anim = model.animations[static_cast<size_t>(index)];
  for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
    const tinygltf::AnimationChannel& ch = anim.channels[ci];
    if (ch.target_node < 0 || static_cast<size_t>(ch.target_node) >= trs->size()) continue;
    const bool is_t = ch.target_path == "translation", is_r = ch.target_path == "rotation",
               is_s = ch.target_path == "scale";
    if (!is_t && !is_r && !is_s) continue;  // morph weights do not move joints
    if (ch.sampler < 0 || static_cast<size_t>(ch.sampler) >= anim.samplers.size())
      return *error = "animation " + std::to_string(index) + ": channel sampler out of range", false;
    const tinygltf::AnimationSampler& s = anim.samplers[static_cast<size_t>(ch.sampler)];
    std::vector<double> in, out;
    int co = 0;
    if (!read_key_times(model, index, s.input, &in, error)) return false;
    if (!read_accessor(model, s.output, 3 * kMaxAnimationKeys, &out, &co, error))
      return *error = "animation " + std::to_string(index) + ": " + *error, false;
    const size_t width = is_r ? 4 : 3;
    const bool cubic = s.interpolation == "CUBICSPLINE";
    const size_t per_key = cubic ? 3 : 1;
    if (in.empty() || static_cast<size_t>(co) != width || out.size() < in.size() * per_key * width)
      return *error = "animation " + std::to_string(index) + ": sampler output does not match its input", false;
    // Key interval containing the (clamped) time.
    const double t = std::clamp(time, in.front(), in.back());
    size_t k = 0;
    while (k + 1 < in.size() && in[k + 1] <= t) ++k;
    const size_t k1 = std::min(k + 1, in.size() - 1);
    const double dt = in[k1] - in[k];
    const double u = dt > 0 ? (t - in[k]) / dt : 0.0;
    const auto value = [&](size_t key, size_t part, size_t c) { return out[(key * per_key + part) * width + c]; };
    std::array<double, 4> v{};
    if (s.interpolation == "STEP" || k == k1) {
      for (size_t c = 0; c < width; ++c) v[c] = value(k, cubic ? 1 : 0, c);
    } else if (cubic) {
      const double u2 = u * u, u3 = u2 * u;
      const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
      for (size_t c = 0; c < width; ++c)
        v[c] = h00 * value(k, 1, c) + h10 * dt * value(k, 2, c) + h01 * value(k1, 1, c) + h11 * dt * value(k1, 0, c);
    } else if (is_r) {
      const Quatd a{value(k, 0, 3), value(k, 0, 0), value(k, 0, 1), value(k, 0, 2)};
      const Quatd b{value(k1, 0, 3), value(k1, 0, 0), value(k1, 0, 1), value(k1, 0, 2)};
      const Quatd q = slerp(a, b, u);
      v = {q[1], q[2], q[3], q[0]};
    } else {
      for (size_t c = 0; c < width; ++c) v[c] = (1 - u) * value(k, 0, c) + u * value(k1, 0, c);
    }
    for (size_t c = 0; c < width; ++c)
      if (!std::isfinite(v[c]))
        return *error = "animation " + std::to_string(index) + " channel " + std::to_string(ci) + ": the " +
                        ch.target_path + " of node " + std::to_string(ch.target_node) + " is not finite at time " +
                        std::to_string(time),
               false;
    NodeTrs& node = (*trs)[static_cast<size_t>(ch.target_node)];
    if (is_t) node.translation = {v[0], v[1], v[2]};
    if (is_s) node.scale = {v[0], v[1], v[2]};
    if (is_r) node.rotation = normalized({v[3], v[0], v[1], v[2]});  // glTF stores x, y, z, w
  }
  return true;
}

}  // namespace sinew::rigc
