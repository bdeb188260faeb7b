#include "builtin_rigs.hpp"

#include <algorithm>
#include <cmath>

#include "sim_core/fixed/trig.hpp"

namespace sinew::rigc {
namespace {

// cos/sin of k/n of a turn from sim_core's integer trig: identical everywhere.
void ring_direction(int k, int n, double* c, double* s) {
  const fx::Angle a = static_cast<fx::Angle>((uint64_t{1} << 32) * static_cast<uint64_t>(k) / static_cast<uint64_t>(n));
  const fx::SinCos sc = fx::sin_cos(a);
  *c = std::ldexp(static_cast<double>(sc.cos), -30);
  *s = std::ldexp(static_cast<double>(sc.sin), -30);
}

double smoothstep(double x) {
  const double t = std::clamp(x, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

struct ChainJoint {
  int joint;  // rig joint index
  double x;   // position along the chain axis (model space)
};

// A tube along +x from chain.front().x to end_x, centred at (y0, z0), with
// radius(x); every ring blends the two nearest chain joints over +-blend
// around each joint. Elliptic cross-section via (ry, rz) scale factors.
void add_tube(RigSpec* spec, const std::vector<ChainJoint>& chain, double end_x, double y0, double z0,
              double (*radius)(double), double ry, double rz, double ring_step, int segments, double blend,
              bool dual_quaternion) {
  const uint32_t first = static_cast<uint32_t>(spec->vertices.size());
  const double start = chain.front().x;
  const int rings = static_cast<int>(std::floor((end_x - start) / ring_step)) + 1;
  for (int r = 0; r < rings; ++r) {
    const double x = start + ring_step * r;
    // Bone of this ring: the last chain joint at or before x.
    size_t b = 0;
    while (b + 1 < chain.size() && chain[b + 1].x <= x) ++b;
    std::vector<Influence> inf;
    const double to_next = b + 1 < chain.size() ? chain[b + 1].x - x : 1e9;
    const double from_this = x - chain[b].x;
    if (to_next < blend) {  // approaching the next joint
      const double w = 0.5 * smoothstep((blend - to_next) / blend);
      inf = {{chain[b].joint, 1 - w}, {chain[b + 1].joint, w}};
    } else if (b > 0 && from_this < blend) {  // just past this joint
      const double w = 0.5 + 0.5 * smoothstep(from_this / blend);
      inf = {{chain[b].joint, w}, {chain[b - 1].joint, 1 - w}};
    } else {
      inf = {{chain[b].joint, 1.0}};
    }
    const double rad = radius(x);
    for (int k = 0; k < segments; ++k) {
      double c, s;
      ring_direction(k, segments, &c, &s);
      VertexSpec v;
      v.position = {x, y0 + rad * ry * c, z0 + rad * rz * s};
      v.normal = {0, rz * c, ry * s};
      v.influences = inf;
      v.dual_quaternion = dual_quaternion;
      spec->vertices.push_back(v);
    }
  }
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const uint32_t a = first + static_cast<uint32_t>(r * segments + k);
      const uint32_t b = first + static_cast<uint32_t>(r * segments + (k + 1) % segments);
      const uint32_t c = a + static_cast<uint32_t>(segments), d = b + static_cast<uint32_t>(segments);
      spec->triangles.push_back({a, c, b});
      spec->triangles.push_back({b, c, d});
    }
  spec->primitives.push_back({first, static_cast<uint32_t>(spec->vertices.size()) - first});
}

int add_joint(RigSpec* spec, const std::string& name, int parent, Vec3d offset, DofKind kind,
              std::vector<DofSpec> dofs) {
  JointSpec j;
  j.name = name;
  j.parent = parent;
  j.translation = offset;
  j.dof_kind = kind;
  j.dofs = std::move(dofs);
  spec->joints.push_back(j);
  return static_cast<int>(spec->joints.size()) - 1;
}

// Palette: one entry per joint; rest rotations are identity, so the inverse
// bind is a translation by minus the joint's model-space position.
void add_palette(RigSpec* spec) {
  std::vector<Vec3d> model(spec->joints.size());
  for (size_t j = 0; j < spec->joints.size(); ++j) {
    const JointSpec& js = spec->joints[j];
    const Vec3d base = js.parent >= 0 ? model[static_cast<size_t>(js.parent)] : Vec3d{0, 0, 0};
    model[j] = {base[0] + js.translation[0], base[1] + js.translation[1], base[2] + js.translation[2]};
    PaletteSpec p;
    p.joint = static_cast<int>(j);
    p.inverse_bind[12] = -model[j][0];
    p.inverse_bind[13] = -model[j][1];
    p.inverse_bind[14] = -model[j][2];
    spec->palette.push_back(p);
  }
}

double arm_radius(double x) {
  // Upper arm 5 cm, forearm tapering to 3 cm at the wrist, hand 2.5 cm.
  if (x < 0.30) return 0.050 - 0.010 * smoothstep((x - 0.22) / 0.08);
  if (x < 0.55) return 0.040 - 0.010 * (x - 0.30) / 0.25;
  return 0.030 - 0.005 * smoothstep((x - 0.55) / 0.05);
}

double finger_radius(double) { return 0.0085; }
double palm_radius(double) { return 0.040; }

}  // namespace

RigSpec builtin_arm(SkinChoice method) {
  RigSpec s;
  const DofKind rot = DofKind::kRotation;
  const int shoulder = add_joint(&s, "shoulder", -1, {0, 0, 0}, rot,
                                 {{{0, 0, 1}, -90, 150}, {{0, 1, 0}, -90, 90}, {{1, 0, 0}, -90, 90}});
  const int elbow = add_joint(&s, "elbow", shoulder, {0.30, 0, 0}, rot, {{{0, 0, 1}, 0, 150}});
  const int twist = add_joint(&s, "forearm_twist", elbow, {0.12, 0, 0}, rot, {{{1, 0, 0}, -100, 100}});
  const int wrist = add_joint(&s, "wrist", twist, {0.13, 0, 0}, rot, {{{0, 0, 1}, -70, 80}, {{0, 1, 0}, -20, 35}});
  add_palette(&s);
  add_tube(&s, {{shoulder, 0.0}, {elbow, 0.30}, {twist, 0.42}, {wrist, 0.55}}, 0.65, 0, 0, arm_radius, 1, 1, 0.005,
           kArmRingSegments, 0.06, method == SkinChoice::kDualQuaternion);
  return s;
}

RigSpec builtin_hand(SkinChoice method) {
  RigSpec s;
  const DofKind rot = DofKind::kRotation;
  const bool dq = method == SkinChoice::kDualQuaternion;
  const int wrist = add_joint(&s, "wrist", -1, {0, 0, 0}, rot, {{{0, 0, 1}, -70, 80}, {{0, 1, 0}, -20, 35}});
  struct Finger {
    const char* name;
    double y, length0, length1, length2, base_x;
  };
  const Finger fingers[] = {{"thumb", -0.035, 0.040, 0.032, 0.025, 0.025},
                            {"index", -0.024, 0.045, 0.026, 0.020, 0.090},
                            {"middle", -0.006, 0.048, 0.029, 0.022, 0.092},
                            {"ring", 0.012, 0.045, 0.027, 0.021, 0.090},
                            {"little", 0.029, 0.036, 0.021, 0.018, 0.085}};
  std::vector<std::vector<ChainJoint>> chains;
  for (const Finger& f : fingers) {
    const std::string n = f.name;
    const int mcp =
        add_joint(&s, n + "_mcp", wrist, {f.base_x, f.y, 0}, rot, {{{0, 1, 0}, -20, 90}, {{0, 0, 1}, -20, 20}});
    const int pip = add_joint(&s, n + "_pip", mcp, {f.length0, 0, 0}, rot, {{{0, 1, 0}, 0, 110}});
    const int dip = add_joint(&s, n + "_dip", pip, {f.length1, 0, 0}, rot, {{{0, 1, 0}, -10, 90}});
    chains.push_back({{mcp, f.base_x}, {pip, f.base_x + f.length0}, {dip, f.base_x + f.length0 + f.length1}});
  }
  // DIP follows 2/3 of the PIP flexion (the coupling of the flexor tendons;
  // anatomically-based §3 synergies). Inputs follow joint order: wrist 0-1,
  // then per finger MCP (2), PIP (1), DIP (1).
  for (int f = 0; f < 5; ++f) {
    const int pip_input = 2 + f * 4 + 2;
    const int dip_joint = 1 + f * 3 + 2;
    s.synergies.push_back({pip_input, dip_joint, 0, 2.0 / 3.0});
  }
  add_palette(&s);
  add_tube(&s, {{wrist, -0.02}}, 0.085, 0, 0, palm_radius, 1.0, 0.35, 0.003, 32, 0.02, dq);
  for (size_t f = 0; f < 5; ++f) {
    const Finger& fi = fingers[f];
    const double end = fi.base_x + fi.length0 + fi.length1 + fi.length2;
    add_tube(&s, chains[f], end, fi.y, 0, finger_radius, 1, 1, 0.003, 16, 0.008, dq);
  }
  return s;
}

bool builtin_rig(const std::string& name, SkinChoice method, RigSpec* out) {
  if (name == "arm") return *out = builtin_arm(method), true;
  if (name == "hand") return *out = builtin_hand(method), true;
  return false;
}

std::vector<std::string> input_names(const RigSpec& spec) {
  std::vector<std::string> names;
  for (const JointSpec& j : spec.joints)
    for (size_t d = 0; d < j.dofs.size(); ++d) names.push_back(j.name + "." + std::to_string(d));
  return names;
}

int joint_index(const RigSpec& spec, const std::string& name) {
  for (size_t j = 0; j < spec.joints.size(); ++j)
    if (spec.joints[j].name == name) return static_cast<int>(j);
  return -1;
}

}  // namespace sinew::rigc
