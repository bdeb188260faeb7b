// The offline rig description, in double precision. Importers (glTF, the
// built-in procedural rigs, TOML specs) fill it; compile_rig() quantises it
// into the binary format of sim_core/rig/rig_format.hpp.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sinew::rigc {

using Vec3d = std::array<double, 3>;
using Quatd = std::array<double, 4>;   // w, x, y, z
using Mat4d = std::array<double, 16>;  // column-major, as glTF

enum class DofKind { kRotation, kTranslation };

struct DofSpec {
  Vec3d axis{1, 0, 0};           // unit axis in the joint's rest frame
  double min = -180, max = 180;  // degrees (rotation) or model units (translation)
};

struct JointSpec {
  std::string name;
  int parent = -1;  // must precede the joint
  Vec3d translation{0, 0, 0};
  Quatd rotation{1, 0, 0, 0};
  Vec3d scale{1, 1, 1};
  DofKind dof_kind = DofKind::kRotation;
  std::vector<DofSpec> dofs;  // 0..3
};

struct SynergySpec {
  int source_input = 0;  // index into the rig's inputs (DOFs in joint order)
  int target_joint = 0;
  int target_dof = 0;
  double gain = 1.0;
  // false: the target adds gain x source (a coupling; the source keeps its
  // command). true: gain is the target's share of the command, taken from
  // the source's own DOF (a chain, anatomically-based §3; blob major 2).
  bool share = false;
};

struct PaletteSpec {
  int joint = 0;
  Mat4d inverse_bind{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

struct Influence {
  int palette = 0;
  double weight = 0;
};

struct VertexSpec {
  Vec3d position{0, 0, 0};
  Vec3d normal{0, 0, 1};
  std::vector<Influence> influences;
  bool dual_quaternion = false;
};

struct RigSpec {
  std::vector<JointSpec> joints;
  std::vector<SynergySpec> synergies;
  std::vector<PaletteSpec> palette;
  std::vector<VertexSpec> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<std::array<uint32_t, 2>> primitives;  // first vertex, count
  bool has_normals = true;
  // Extra magnitudes the rig must represent (e.g. animated translations), in
  // model units; considered when choosing the length exponent.
  double extra_extent = 0;
  // For rigs imported from glTF: the node each joint comes from (a spec may
  // name a joint by node index where the file leaves nodes unnamed).
  std::vector<int> source_node;
};

struct CompileReport {
  uint32_t joints = 0, inputs = 0, vertices = 0, triangles = 0, palette = 0;
  uint32_t influences_per_vertex = 0;
  uint32_t renormalized_vertices = 0;  // weight sums that were not 1 (beyond 1e-6)
  int32_t length_exponent = 0;
  // The exponent the extent asked for lay outside the format's range, so it
  // was clamped: coordinates saturate (too large) or lose precision (too small).
  bool length_exponent_clamped = false;
  double extent = 0;  // the largest magnitude considered, in model units
  size_t blob_bytes = 0, rig_arena_bytes = 0, engine_arena_bytes = 0;
};

// Returns false with a message naming the problem (joint/vertex index and field).
bool compile_rig(const RigSpec& spec, std::vector<uint8_t>* blob, CompileReport* report, std::string* error);

// The length exponent compile_rig chooses: one rig unit = 2^e model units, so
// the largest magnitude uses at most 1/8 of the Q12.20 range.
int32_t choose_length_exponent(const RigSpec& spec);
// The same before clamping to the format's range (0 for an empty rig).
int32_t unclamped_length_exponent(const RigSpec& spec, double* extent = nullptr);

std::string format_report(const CompileReport& r);

}  // namespace sinew::rigc
