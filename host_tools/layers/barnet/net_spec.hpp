// Offline description of a bar-net in double precision (model units of the
// rig it drives), and the builder that quantises it into a runtime
// barnet::BarnetModel: free nodes first, force densities in Q16.16, loads in Q8.24, and the wrap binding of the
// fine skin (closest control triangle, barycentric coordinates and a normal
// offset). Only + - * / and std::sqrt: the output is bit-identical on every
// platform (compiled with -ffp-contract=off).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/barnet/barnet_model.hpp"

namespace sinew::layers::barnet {

using rigc::Vec3d;

struct NodeSpec {
  Vec3d rest{0, 0, 0};
  bool fixed = true;
  std::vector<rigc::Influence> influences;  // palette index (as in the rig) and weight
};

struct BarSpec {
  uint32_t a = 0, b = 0;
  double q = 1.0;  // force density
};

struct LoadSpec {
  uint32_t node = 0;
  int joint = 0;                       // bone whose skinning matrix carries the force
  int input = 0;                       // rig input whose angle activates it
  double angle_lo = 0, angle_hi = 90;  // degrees: activation 0 at lo, 1 at hi
  Vec3d force{0, 0, 0};                // at full activation, bind-pose model frame, q x model units
  // >= 0: the external input (EXTI index) activating it instead of `input`,
  // 0 at value_lo, 1 at value_hi (the input's unit, e.g. newtons).
  int external_input = -1;
  double value_lo = 0, value_hi = 1;
};

// Bars [first_bar, first_bar + bar_count) whose q is scaled by an external
// input's value (dimensionless, clamped to [1/256, 256]) every step.
struct ForceDensityInputSpec {
  int external_input = 0;  // EXTI index
  uint32_t first_bar = 0, bar_count = 0;
};

struct NetSpec {
  std::vector<NodeSpec> nodes;
  std::vector<BarSpec> bars;
  std::vector<LoadSpec> loads;
  std::vector<std::array<uint32_t, 3>> triangles;  // control mesh
  std::vector<uint32_t> wrap_vertices;             // fine skin vertices bound to the control mesh
  uint32_t external_count = 0;                     // external inputs of the rig (EXTI), for loads and q_inputs
  std::vector<ForceDensityInputSpec> q_inputs;     // bars keep the spec's order, so runs index spec bars
  // Order the free nodes by reverse Cuthill-McKee over the bars between
  // them (the default) instead of keeping the spec's order: a smaller
  // skyline profile, hence a cheaper factor and solve (ldlt_skyline.hpp;
  // 2171 -> 605 entries on the 224-node elbow net). The solution is the same
  // net's; only its rounding (<= 1 Len LSB) differs.
  bool profile_order = true;
  // The volume-keeping push (volume_loads.hpp), when the net has one: the
  // schedule's steps and those no push in reach could restore (they hold
  // the previous step's push); reported by rigc. Offline only: not in the
  // blob.
  int volume_steps = 0;
  int volume_short_steps = 0;
};

// The quantised model and the arrays it points into.
struct BarnetBuild {
  int32_t length_exponent = 0;  // the rig's: one rig unit = 2^e model units
  uint32_t joint_count = 0, input_count = 0, vertex_count = 0, external_count = 0;
  std::vector<fx::Mat34> inverse_bind;
  std::vector<sinew::barnet::NodeRecord> nodes;
  std::vector<sinew::barnet::BarRecord> bars;
  std::vector<sinew::barnet::LoadRecord> loads;
  std::vector<sinew::barnet::ControlTriangle> triangles;
  std::vector<sinew::barnet::WrapRecord> wrap;
  std::vector<sinew::barnet::ForceDensityInput> q_inputs;
  std::vector<uint32_t> node_order;  // spec node index -> model node index
  double max_wrap_offset = 0;        // largest |offset| of the wrap binding (model units)

  sinew::barnet::BarnetModel model() const;
};

// The control mesh of a tube whose nodes are numbered ring by ring
// (node(ring, k) = ring x segments + k mod segments): two triangles per
// quad, wound so that cross(b - a, c - a) points outwards when rings advance
// along the axis and k turns counter-clockwise about it; their edges become
// the bars, each with force density q.
void add_tube_mesh(int rings, int segments, double q, NetSpec* net);

// The first rig input of `joint` (inputs are the joints' DOFs in joint order).
int first_input_of(const rigc::RigSpec& rig, int joint);

// Drives a built net from external inputs (EXTI indices; -1: none): every
// load's activation follows `force_input` (0 at value_lo, 1 at value_hi)
// instead of its joint angle, and every bar's q is scaled by `q_input` (one
// run over all bars, re-factorised every step).
struct InputDrive {
  uint32_t external_count = 0;
  int force_input = -1;
  double value_lo = 0, value_hi = 40;
  int q_input = -1;
};
void drive_from_inputs(const InputDrive& drive, NetSpec* net);

// Returns false with a message naming the spec record and field.
bool build_barnet(const NetSpec& spec, const rigc::RigSpec& rig, BarnetBuild* out, std::string* error);

}  // namespace sinew::layers::barnet
