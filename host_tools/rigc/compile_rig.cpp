// RigSpec -> binary rig v1 (docs/rig-format.md).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "quantize.hpp"
#include "rig_spec.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/rig/crc32c.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::rigc {
namespace {

namespace fmt = sinew::rig;

constexpr size_t align8(size_t v) { return (v + 7u) & ~size_t{7}; }

struct Writer {
  std::vector<uint8_t> bytes;
  std::vector<fmt::SectionEntry> table;
  void section(uint32_t id, const void* data, size_t size) {
    bytes.resize(align8(bytes.size()));
    table.push_back({id, static_cast<uint32_t>(bytes.size()), static_cast<uint32_t>(align8(size)), 0});
    const size_t at = bytes.size();
    bytes.resize(at + align8(size), 0);
    if (size > 0) std::memcpy(bytes.data() + at, data, size);
  }
};

bool finite3(const Vec3d& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

double max_abs(const Vec3d& v) { return std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])}); }

std::string at(const char* what, size_t index, const char* field, const std::string& problem) {
  std::ostringstream s;
  s << what << "[" << index << "]." << field << ": " << problem;
  return s.str();
}

std::array<int32_t, 4> quantize_quat(Quatd q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  std::array<int32_t, 4> out{};
  for (int i = 0; i < 4; ++i) out[static_cast<size_t>(i)] = to_fixed(q[static_cast<size_t>(i)] / n, 30);
  return out;
}

// The joint whose DOFs own input `input` (rigc assigns inputs in joint order).
int joint_of_input(const RigSpec& spec, int input) {
  int first = 0;
  for (size_t j = 0; j < spec.joints.size(); ++j) {
    first += static_cast<int>(spec.joints[j].dofs.size());
    if (input < first) return static_cast<int>(j);
  }
  return -1;
}

int32_t limit_angle(double degrees) { return to_fixed(std::clamp(degrees, -180.0, 180.0) / 360.0, 32); }

}  // namespace

int32_t unclamped_length_exponent(const RigSpec& spec, double* extent_out) {
  double extent = spec.extra_extent;
  for (const VertexSpec& v : spec.vertices) extent = std::max(extent, max_abs(v.position));
  for (const JointSpec& j : spec.joints) extent = std::max(extent, max_abs(j.translation));
  for (const PaletteSpec& p : spec.palette)
    extent =
        std::max({extent, std::fabs(p.inverse_bind[12]), std::fabs(p.inverse_bind[13]), std::fabs(p.inverse_bind[14])});
  if (extent_out != nullptr) *extent_out = extent;
  if (!(extent > 0) || !std::isfinite(extent)) return 0;
  // Largest magnitude at most 256 rig units (1/8 of Q12.20's range):
  // e = ceil(log2(extent / 256)), exactly, via frexp (no libm rounding).
  int k = 0;
  const double m = std::frexp(extent / 256.0, &k);  // extent / 256 = m * 2^k, m in [0.5, 1)
  return m == 0.5 ? k - 1 : k;
}

int32_t choose_length_exponent(const RigSpec& spec) {
  return std::clamp(unclamped_length_exponent(spec), fmt::kMinLengthExponent, fmt::kMaxLengthExponent);
}

bool compile_rig(const RigSpec& spec, std::vector<uint8_t>* blob, CompileReport* report, std::string* error) {
  const size_t nj = spec.joints.size(), nv = spec.vertices.size(), np = spec.palette.size();
  if (nj == 0) return *error = "rig: no joints", false;
  if (nj > fmt::kMaxJoints) return *error = "rig: more than 1024 joints", false;
  if (nv > fmt::kMaxVertices) return *error = "rig: more than 2^20 vertices", false;
  if (np > fmt::kMaxPalette) return *error = "rig: more than 4096 palette entries", false;
  if (nv > 0 && np == 0) return *error = "rig: a skin needs at least one palette entry", false;
  const int32_t e = choose_length_exponent(spec);

  // Joints and inputs.
  std::vector<fmt::JointRecord> joints(nj);
  std::vector<char> names(nj * fmt::kNameBytes, 0);
  uint32_t inputs = 0;
  for (size_t j = 0; j < nj; ++j) {
    const JointSpec& s = spec.joints[j];
    if (s.parent < -1 || s.parent >= static_cast<int>(j))
      return *error = at("joint", j, "parent", "must be -1 or an earlier joint (parents first)"), false;
    if (s.dofs.size() > 3) return *error = at("joint", j, "dofs", "at most 3 degrees of freedom"), false;
    if (!finite3(s.translation) || !finite3(s.scale))
      return *error = at("joint", j, "translation", "not finite"), false;
    for (double c : s.scale)
      if (!(std::fabs(c) < 127.0)) return *error = at("joint", j, "scale", "outside the Q8.24 range (+-127)"), false;
    fmt::JointRecord& r = joints[j];
    r = {};
    r.parent = s.parent;
    r.dof_count = static_cast<uint8_t>(s.dofs.size());
    r.dof_kind =
        static_cast<uint8_t>(s.dof_kind == DofKind::kRotation ? fmt::DofKind::kRotation : fmt::DofKind::kTranslation);
    r.first_input = static_cast<uint16_t>(inputs);
    inputs += r.dof_count;
    for (int c = 0; c < 3; ++c) {
      r.rest_translation[c] = to_len(s.translation[static_cast<size_t>(c)], e);
      r.rest_scale[c] = to_fixed(s.scale[static_cast<size_t>(c)], 24);
    }
    const auto q = quantize_quat(s.rotation);
    std::copy(q.begin(), q.end(), r.rest_rotation);
    for (size_t d = 0; d < s.dofs.size(); ++d) {
      const DofSpec& dof = s.dofs[d];
      const double n = std::sqrt(dof.axis[0] * dof.axis[0] + dof.axis[1] * dof.axis[1] + dof.axis[2] * dof.axis[2]);
      if (!(n > 1e-9)) return *error = at("joint", j, "dof axis", "zero or not finite"), false;
      if (!(dof.min <= dof.max)) return *error = at("joint", j, "dof limits", "min greater than max"), false;
      for (int c = 0; c < 3; ++c) r.dof_axis[d][c] = to_fixed(dof.axis[static_cast<size_t>(c)] / n, 30);
      if (s.dof_kind == DofKind::kRotation) {
        r.dof_min[d] = limit_angle(dof.min);
        r.dof_max[d] = limit_angle(dof.max);
      } else {
        r.dof_min[d] = to_len(dof.min, e);
        r.dof_max[d] = to_len(dof.max, e);
      }
    }
    std::strncpy(&names[j * fmt::kNameBytes], s.name.c_str(), fmt::kNameBytes - 1);
  }
  std::vector<fmt::SynergyRecord> synergies;
  bool any_share = false;  // shared synergies need major 2; without them the blob stays 1.x
  for (size_t i = 0; i < spec.synergies.size(); ++i) {
    const SynergySpec& s = spec.synergies[i];
    if (s.source_input < 0 || static_cast<uint32_t>(s.source_input) >= inputs)
      return *error = at("synergy", i, "source_input", "no such input"), false;
    if (s.target_joint < 0 || static_cast<size_t>(s.target_joint) >= nj || s.target_dof < 0 ||
        static_cast<size_t>(s.target_dof) >= spec.joints[static_cast<size_t>(s.target_joint)].dofs.size())
      return *error = at("synergy", i, "target", "no such joint DOF"), false;
    if (!(std::fabs(s.gain) < 1.99)) return *error = at("synergy", i, "gain", "outside (-2, 2)"), false;
    if (s.share) {
      if (!(s.gain >= 0 && s.gain <= 1)) return *error = at("synergy", i, "gain", "share outside [0, 1]"), false;
      if (s.target_joint == joint_of_input(spec, s.source_input))
        return *error = at("synergy", i, "target", "a share cannot target its source's own joint"), false;
      double shared = 0;  // the source keeps 1 - (its shares), which must not be negative
      for (const SynergySpec& o : spec.synergies)
        if (o.share && o.source_input == s.source_input) shared += o.gain;
      if (shared > 1 + 1e-6) return *error = at("synergy", i, "gain", "the source's shares sum above 1"), false;
      any_share = true;
    }
    fmt::SynergyRecord r{};
    r.source_input = static_cast<uint16_t>(s.source_input);
    r.target_joint = static_cast<uint16_t>(s.target_joint);
    r.target_dof = static_cast<uint8_t>(s.target_dof);
    r.mode = static_cast<uint8_t>(s.share ? fmt::SynergyMode::kShare : fmt::SynergyMode::kAdd);
    r.gain = to_fixed(s.gain, 30);
    synergies.push_back(r);
  }

  // Palette: glTF column-major 4x4 -> Mat34 (Q8.24 linear, Len translation).
  std::vector<fmt::PaletteRecord> palette(np);
  for (size_t p = 0; p < np; ++p) {
    const PaletteSpec& s = spec.palette[p];
    if (s.joint < 0 || static_cast<size_t>(s.joint) >= nj)
      return *error = at("palette", p, "joint", "no such joint"), false;
    palette[p].joint = static_cast<uint32_t>(s.joint);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        const double v = s.inverse_bind[static_cast<size_t>(c * 4 + r)];
        if (!(std::fabs(v) < 64.0))
          return *error = at("palette", p, "inverse_bind", "linear entry outside +-64 or not finite"), false;
        palette[p].inverse_bind.m[r][c] = to_fixed(v, 24);
      }
      palette[p].inverse_bind.t[r] = to_len(s.inverse_bind[static_cast<size_t>(12 + r)], e);
    }
  }

  // Skin: influences sorted by weight, renormalised to sum exactly 2^30.
  size_t k = 1;
  for (size_t v = 0; v < nv; ++v) {
    size_t nonzero = 0;
    for (const Influence& in : spec.vertices[v].influences) nonzero += in.weight > 0 ? 1 : 0;
    if (nonzero > fmt::kMaxInfluences)
      return *error = at("vertex", v, "influences", "more than 8 non-zero influences"), false;
    k = std::max(k, nonzero);
  }
  std::vector<int32_t> pos(3 * nv), nrm(3 * nv);
  std::vector<uint16_t> inf_joint(nv * k, 0);
  std::vector<int32_t> inf_weight(nv * k, 0);
  std::vector<uint8_t> method(nv, 0);
  uint32_t renormalized = 0;
  for (size_t v = 0; v < nv; ++v) {
    const VertexSpec& s = spec.vertices[v];
    if (!finite3(s.position)) return *error = at("vertex", v, "position", "not finite"), false;
    for (int c = 0; c < 3; ++c) {
      pos[static_cast<size_t>(c) * nv + v] = to_len(s.position[static_cast<size_t>(c)], e);
    }
    const double nn = std::sqrt(s.normal[0] * s.normal[0] + s.normal[1] * s.normal[1] + s.normal[2] * s.normal[2]);
    for (int c = 0; c < 3; ++c)
      nrm[static_cast<size_t>(c) * nv + v] =
          nn > 0 && std::isfinite(nn) ? to_fixed(s.normal[static_cast<size_t>(c)] / nn, 30) : 0;
    std::vector<Influence> in;
    double sum = 0;
    for (const Influence& i : s.influences) {
      if (!(i.weight >= 0) || !std::isfinite(i.weight))
        return *error = at("vertex", v, "weight", "negative or not finite"), false;
      if (i.weight == 0) continue;
      if (i.palette < 0 || static_cast<size_t>(i.palette) >= np)
        return *error = at("vertex", v, "joint", "no such palette entry"), false;
      in.push_back(i);
      sum += i.weight;
    }
    if (in.empty() || !(sum > 0)) return *error = at("vertex", v, "weights", "all weights are zero"), false;
    if (std::fabs(sum - 1.0) > 1e-6) ++renormalized;
    std::stable_sort(in.begin(), in.end(), [](const Influence& a, const Influence& b) { return a.weight > b.weight; });
    int64_t total = 0;
    for (size_t i = 0; i < in.size(); ++i) {
      inf_joint[v * k + i] = static_cast<uint16_t>(in[i].palette);
      inf_weight[v * k + i] = to_fixed(in[i].weight / sum, 30);
      total += inf_weight[v * k + i];
    }
    inf_weight[v * k] += static_cast<int32_t>((int64_t{1} << 30) - total);  // exact sum: residue to the largest
    method[v] = s.dual_quaternion ? 1 : 0;
  }
  std::vector<uint32_t> tris;
  for (size_t t = 0; t < spec.triangles.size(); ++t)
    for (uint32_t i : spec.triangles[t]) {
      if (i >= nv) return *error = at("triangle", t, "index", "beyond the vertex count"), false;
      tris.push_back(i);
    }
  std::vector<fmt::PrimitiveRecord> prims;
  for (const auto& p : spec.primitives) prims.push_back({p[0], p[1]});

  // Assemble: header, table, sections; then the CRC.
  Writer w;
  w.bytes.resize(sizeof(fmt::FileHeader));
  const uint32_t section_count = 11;
  const size_t table_offset = w.bytes.size();
  w.bytes.resize(table_offset + section_count * sizeof(fmt::SectionEntry));
  w.section(fmt::kSectionJoints, joints.data(), joints.size() * sizeof(fmt::JointRecord));
  w.section(fmt::kSectionNames, names.data(), names.size());
  w.section(fmt::kSectionSynergies, synergies.data(), synergies.size() * sizeof(fmt::SynergyRecord));
  w.section(fmt::kSectionPalette, palette.data(), palette.size() * sizeof(fmt::PaletteRecord));
  w.section(fmt::kSectionPositions, pos.data(), pos.size() * 4);
  w.section(fmt::kSectionNormals, nrm.data(), spec.has_normals ? nrm.size() * 4 : 0);
  w.section(fmt::kSectionInfluenceJoints, inf_joint.data(), inf_joint.size() * 2);
  w.section(fmt::kSectionInfluenceWeights, inf_weight.data(), inf_weight.size() * 4);
  w.section(fmt::kSectionVertexMethod, method.data(), method.size());
  w.section(fmt::kSectionTriangles, tris.data(), tris.size() * 4);
  w.section(fmt::kSectionPrimitives, prims.data(), prims.size() * sizeof(fmt::PrimitiveRecord));
  if (!spec.has_normals) {
    // An empty VNRM entry would fail the size check: drop it from the table.
    w.table.erase(std::remove_if(w.table.begin(), w.table.end(),
                                 [](const fmt::SectionEntry& s) { return s.id == fmt::kSectionNormals; }),
                  w.table.end());
  }
  w.bytes.resize(align8(w.bytes.size()));
  fmt::FileHeader h{};
  h.magic = fmt::kMagic;
  h.version_major = any_share ? fmt::kVersionMajorShares : fmt::kVersionMajorFirst;
  h.version_minor = fmt::kVersionMinor;
  h.header_size = sizeof(fmt::FileHeader);
  h.total_size = static_cast<uint32_t>(w.bytes.size());
  h.section_count = static_cast<uint32_t>(w.table.size());
  h.section_table_offset = static_cast<uint32_t>(table_offset);
  h.length_exponent = e;
  h.joint_count = static_cast<uint32_t>(nj);
  h.palette_count = static_cast<uint32_t>(np);
  h.vertex_count = static_cast<uint32_t>(nv);
  h.triangle_count = static_cast<uint32_t>(spec.triangles.size());
  h.influences_per_vertex = static_cast<uint32_t>(k);
  h.input_count = inputs;
  h.synergy_count = static_cast<uint32_t>(synergies.size());
  h.primitive_count = static_cast<uint32_t>(prims.size());
  std::memcpy(w.bytes.data(), &h, sizeof(h));
  std::memcpy(w.bytes.data() + table_offset, w.table.data(), w.table.size() * sizeof(fmt::SectionEntry));
  const uint32_t crc = fmt::crc32c(0, w.bytes.data(), w.bytes.size());  // crc field is still zero
  std::memcpy(w.bytes.data() + offsetof(fmt::FileHeader, crc32c), &crc, 4);

  // Round trip through the runtime loader: the compiler never emits a blob the board would reject.
  size_t arena = 0;
  const fmt::LoadStatus st = fmt::rig_validate(w.bytes.data(), w.bytes.size(), &arena);
  if (!st.ok()) return *error = std::string("internal: compiled blob rejected: ") + st.message, false;
  std::vector<uint64_t> arena_mem(arena / 8 + 1);
  fmt::Rig rig;
  fmt::rig_init(w.bytes.data(), w.bytes.size(), arena_mem.data(), arena_mem.size() * 8, &rig);

  report->joints = static_cast<uint32_t>(nj);
  report->inputs = inputs;
  report->vertices = static_cast<uint32_t>(nv);
  report->triangles = static_cast<uint32_t>(spec.triangles.size());
  report->palette = static_cast<uint32_t>(np);
  report->influences_per_vertex = static_cast<uint32_t>(k);
  report->renormalized_vertices = renormalized;
  report->length_exponent = e;
  report->length_exponent_clamped = unclamped_length_exponent(spec, &report->extent) != e;
  report->blob_bytes = w.bytes.size();
  report->rig_arena_bytes = arena;
  report->engine_arena_bytes = engine::engine_arena_bytes(rig);
  *blob = std::move(w.bytes);
  return true;
}

std::string format_report(const CompileReport& r) {
  std::ostringstream s;
  s << "joints " << r.joints << ", inputs " << r.inputs << ", vertices " << r.vertices << ", triangles " << r.triangles
    << ", palette " << r.palette << ", influences/vertex " << r.influences_per_vertex << ", renormalised weights "
    << r.renormalized_vertices << ", rig unit 2^" << r.length_exponent << ", blob " << r.blob_bytes << " B, rig arena "
    << r.rig_arena_bytes << " B, engine arena " << r.engine_arena_bytes << " B";
  return s.str();
}

}  // namespace sinew::rigc
