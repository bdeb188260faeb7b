// Joint collapse on a glTF model (metaballs-pbd-skinning, "Results and
// comparisons"; tests/sim_core/metaballs/volume_test.cpp does the same on the
// built-in arm): the WebXR hand of tests/data/generic_hand_layers.toml,
// compiled with its [metaballs] table as rigc compiles it, loaded as the
// board loads it and stepped by the pipeline with the metaballs stage alone.
// The four fingers flex at their MCP and PIP joints; the whole skin's
// enclosed volume, posed / rest, is compared for LBS, DQS and metaballs.
//
// The three skins of one pose: the spec compiled with every vertex DQS (its
// `skinning = "dqs"`, the default) gives the pipeline's reference R, the
// plain DQS skin, and its output, R + (metaballs - R), the metaballs skin;
// the same spec with every vertex LBS gives the plain LBS skin as its R.
//
// The hand's skeleton is flat (every joint a child of the Armature node,
// the identity) and its joints have no DOF but the two that other layers of
// the spec bend, so the poses are joint transforms (pipeline_step_locals):
// each finger's chain turned as a rigid hierarchy about its MCP (the
// proximal phalanx's joint), the part beyond the PIP (the intermediate
// phalanx's joint) first about the PIP. The joint frames follow WebXR Hand
// Input: -z along the bone, +y towards the back of the hand (the thumb lies
// at -y in the fingers' frames), so flexion turns about each joint's -x.
//
// The measure: the glTF mesh is open only along its seams (1360 vertices at
// 1159 rest positions); with each seam vertex replaced by the first vertex
// at its rest position every directed edge has its reverse once, so the
// welded mesh is closed and its volume is the divergence theorem's sum of
// signed tetrahedra over the rig's triangles (outward winding: > 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/rigc/toml_spec.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace {
namespace gltf_volume {

namespace pl = sinew::pipeline;
using P3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // w, x, y, z
using Position = std::function<P3(uint32_t)>;
using Triangles = std::vector<std::array<uint32_t, 3>>;

const std::string kHandSpec = std::string(SINEW_SOURCE_DIR) + "/tests/data/generic_hand_layers.toml";
const char* const kFingers[] = {"index", "middle", "ring", "pinky"};

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const P3& a) { return std::sqrt(dot(a, a)); }

Quat qmul(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
// q v q* for a unit q.
P3 qrot(const Quat& q, const P3& v) {
  const P3 u{q[1], q[2], q[3]}, t = cross(u, v);
  const P3 t2{2 * t[0], 2 * t[1], 2 * t[2]}, c = cross(u, t2);
  return {v[0] + q[0] * t2[0] + c[0], v[1] + q[0] * t2[1] + c[1], v[2] + q[0] * t2[2] + c[2]};
}

// A rotation about a unit axis through a pivot.
struct Turn {
  Quat q;
  P3 pivot;
  P3 point(const P3& p) const {
    const P3 r = qrot(q, sub(p, pivot));
    return {pivot[0] + r[0], pivot[1] + r[1], pivot[2] + r[2]};
  }
};
Turn turn(const P3& axis, double degrees, const P3& pivot) {
  const double h = degrees * std::numbers::pi / 360.0, s = std::sin(h);
  return {{std::cos(h), s * axis[0], s * axis[1], s * axis[2]}, pivot};
}

// The hand compiled with every vertex DQS (`dqs`) or LBS and started with
// the metaballs stage alone on (the skinning always runs).
struct Hand {
  std::unique_ptr<sinew::test::LoadedLayers> loaded;
  sinew::rigc::RigSpec spec;
  std::vector<sinew::skeleton::LocalPose> locals;

  bool build(bool dqs, std::string* error) {
    sinew::layers::LayerSpecs layers;
    if (!sinew::rigc::load_toml_rig(kHandSpec, &spec, &layers, error)) return false;
    for (sinew::rigc::VertexSpec& v : spec.vertices) v.dual_quaternion = dqs;
    loaded = sinew::test::compiled_with_layers(spec, layers, error);
    if (loaded == nullptr) return false;
    if (!loaded->layers.metaballs.present) return *error = "the hand has no metaballs section", false;
    pl::PipelineOptions options;
    options.stages = pl::StageSet::none();
    options.stages.set(pl::Stage::kSkinning, true);
    options.stages.set(pl::Stage::kMetaballs, true);
    if (!loaded->start(options, error)) return false;
    locals.resize(loaded->rig.joint_count());
    return true;
  }

  const sinew::rig::Rig& rig() const { return loaded->rig; }
  double lsb() const { return std::ldexp(1.0, rig().length_exponent - 20); }  // metres per Len
  int joint(const std::string& name) const {
    const std::string stored = name.substr(0, sinew::rig::kNameBytes - 1);  // names keep 31 bytes
    for (size_t j = 0; j < spec.joints.size(); ++j)
      if (spec.joints[j].name == stored) return static_cast<int>(j);
    ADD_FAILURE() << "no joint " << name;
    return 0;
  }

  // Every finger's MCP flexed by `mcp` and PIP by `pip` degrees, then one
  // pipeline step from those joint transforms.
  bool pose(double mcp, double pip) {
    sinew::skeleton::rest_locals(rig(), locals);
    const double len = lsb(), unit = std::ldexp(1.0, 30);
    const auto rest_t = [&](int j) {
      const sinew::fx::Vec3& t = locals[static_cast<size_t>(j)].translation;
      return P3{t.x * len, t.y * len, t.z * len};
    };
    const auto rest_q = [&](int j) {
      const sinew::fx::Quat& q = locals[static_cast<size_t>(j)].rotation;
      return Quat{q.w / unit, q.x / unit, q.y / unit, q.z / unit};
    };
    // Flexion of joint j: about its -x, through it (locals are model
    // transforms here: every joint's parent is the identity).
    const auto flexion = [&](int j, double degrees) { return turn(qrot(rest_q(j), {-1, 0, 0}), degrees, rest_t(j)); };
    std::vector<std::pair<int, std::vector<Turn>>> moved;
    for (const char* finger : kFingers) {
      const std::string f = std::string(finger) + "-finger-";
      const int proximal = joint(f + "phalanx-proximal"), intermediate = joint(f + "phalanx-intermediate");
      const Turn at_mcp = flexion(proximal, mcp), at_pip = flexion(intermediate, pip);
      moved.push_back({proximal, {at_mcp}});
      for (const char* beyond : {"phalanx-intermediate", "phalanx-distal", "tip"})
        moved.push_back({joint(f + beyond), {at_pip, at_mcp}});
    }
    std::vector<sinew::skeleton::LocalPose> posed(locals);
    for (const auto& [j, turns] : moved) {
      P3 t = rest_t(j);
      Quat q = rest_q(j);
      for (const Turn& g : turns) t = g.point(t), q = qmul(g.q, q);
      sinew::skeleton::LocalPose& out = posed[static_cast<size_t>(j)];
      out.translation = {static_cast<int32_t>(std::lround(t[0] / len)), static_cast<int32_t>(std::lround(t[1] / len)),
                         static_cast<int32_t>(std::lround(t[2] / len))};
      out.rotation = {static_cast<int32_t>(std::lround(q[0] * unit)), static_cast<int32_t>(std::lround(q[1] * unit)),
                      static_cast<int32_t>(std::lround(q[2] * unit)), static_cast<int32_t>(std::lround(q[3] * unit))};
    }
    const std::vector<int32_t> external(loaded->pipeline.input_count - rig().input_count, 0);
    const pl::PipelineStatus st = pl::pipeline_step_locals(&loaded->pipeline, posed, external);
    if (!st.ok()) ADD_FAILURE() << st.message;
    return st.ok();
  }

  // Metres: the plain skin R, the pipeline's output, the rest mesh.
  P3 plain(uint32_t v) const { return at(loaded->pipeline.reference, v); }
  P3 output(uint32_t v) const { return at(loaded->pipeline.engine.vertices.position, v); }
  P3 rest(uint32_t v) const { return at(rig().position, v); }

 private:
  template <typename Spans>
  P3 at(const Spans& s, uint32_t v) const {
    return {s[0][v] * lsb(), s[1][v] * lsb(), s[2][v] * lsb()};
  }
};

// The rig's triangles, each seam vertex replaced by the first vertex at its
// (fixed-point, so exactly equal) rest position; `open_edges` counts the
// directed edges without exactly one reverse.
Triangles welded_triangles(const sinew::rig::Rig& rig, size_t* open_edges) {
  std::map<std::array<int32_t, 3>, uint32_t> first;
  std::vector<uint32_t> id(rig.vertex_count());
  for (uint32_t v = 0; v < rig.vertex_count(); ++v)
    id[v] = first.emplace(std::array<int32_t, 3>{rig.position[0][v], rig.position[1][v], rig.position[2][v]}, v)
                .first->second;
  Triangles tris;
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t t = 0; t + 2 < rig.triangles.size(); t += 3) {
    const std::array<uint32_t, 3> tri{id[rig.triangles[t]], id[rig.triangles[t + 1]], id[rig.triangles[t + 2]]};
    tris.push_back(tri);
    for (size_t k = 0; k < 3; ++k) ++edges[{tri[k], tri[(k + 1) % 3]}];
  }
  *open_edges = 0;
  for (const auto& [e, n] : edges) {
    const auto reverse = edges.find({e.second, e.first});
    if (n != 1 || reverse == edges.end() || reverse->second != 1) ++*open_edges;
  }
  return tris;
}

double volume(const Triangles& tris, const Position& p) {
  double six_v = 0;
  for (const auto& t : tris) six_v += dot(p(t[0]), cross(p(t[1]), p(t[2])));
  return six_v / 6;
}

double area(const Triangles& tris, const Position& p) {
  double a = 0;
  for (const auto& t : tris) a += 0.5 * norm(cross(sub(p(t[1]), p(t[0])), sub(p(t[2]), p(t[0]))));
  return a;
}

// Flexes every finger's MCP and PIP, prints the three volume ratios and
// asserts the paper's claim against DQS where LBS collapses.
void compare(double mcp, double pip) {
  Hand dqs, lbs;
  std::string error;
  ASSERT_TRUE(dqs.build(true, &error)) << error;
  ASSERT_TRUE(lbs.build(false, &error)) << error;
  size_t open_edges = 0;
  const Triangles tris = welded_triangles(dqs.rig(), &open_edges);
  ASSERT_EQ(open_edges, 0u) << "the welded hand is not a closed surface";
  const double v_rest = volume(tris, [&](uint32_t v) { return dqs.rest(v); });
  ASSERT_GT(v_rest, 0);

  ASSERT_TRUE(dqs.pose(mcp, pip));
  ASSERT_TRUE(lbs.pose(mcp, pip));
  const Position p_lbs = [&](uint32_t v) { return lbs.plain(v); };
  const Position p_dqs = [&](uint32_t v) { return dqs.plain(v); };
  const Position p_mb = [&](uint32_t v) { return dqs.output(v); };
  const double r_lbs = volume(tris, p_lbs) / v_rest, r_dqs = volume(tris, p_dqs) / v_rest,
               r_mb = volume(tris, p_mb) / v_rest;

  // Tolerance from rounding. Moving vertex v by e_v changes the volume by
  // sum_v e_v . (1/3) sum_{t at v} A_t to first order (A_t the area vector
  // of triangle t: the gradient of the sum of tetrahedra on a closed
  // surface), so by at most max |e_v| x the surface area S. Given the joint
  // transforms both read, each metaballs vertex is within five roundings of
  // a Len vector, sqrt(3) / 2 LSB each, of its exact motion
  // (docs/metaballs.md, the step's numerics): 2.5 sqrt(3) LSB; each DQS
  // vertex within 4 LSB a coordinate (docs/numerics.md, the dual quaternion
  // transform's worst error): 4 sqrt(3) LSB. The rest volume is the same
  // quantised mesh's for all three, so the two ratios differ by rounding by
  // at most (2.5 + 4) sqrt(3) LSB x S / V_rest; the second-order terms (LSB^2
  // x edge lengths) are ~1e-9 of that.
  const double s_posed = std::max(area(tris, p_dqs), area(tris, p_mb));
  const double tol = (2.5 + 4.0) * std::sqrt(3.0) * dqs.lsb() * s_posed / v_rest;
  std::printf(
      "glTF hand, four fingers MCP %.0f / PIP %.0f deg: whole-skin volume / rest LBS %.6f DQS %.6f metaballs %.6f "
      "(metaballs - DQS %+.3e, rounding tolerance %.2e; rest %.4g m^3, %zu triangles welded)\n",
      mcp, pip, r_lbs, r_dqs, r_mb, r_mb - r_dqs, tol, v_rest, tris.size());

  if (mcp == 0 && pip == 0) {
    // The rest pose: all three skins give the rest mesh's volume.
    for (const double r : {r_lbs, r_dqs, r_mb}) EXPECT_NEAR(r, 1.0, tol);
    return;
  }
  // The pose exercises the collapse: LBS loses volume that DQS keeps.
  EXPECT_LT(r_lbs, r_dqs - tol) << "MCP " << mcp << " PIP " << pip;
  // The paper's claim: metaballs keep at least DQS's volume, within both
  // skins' rounding of the measure.
  EXPECT_GE(r_mb, r_dqs - tol) << "MCP " << mcp << " PIP " << pip;
}

}  // namespace gltf_volume
}  // namespace

TEST(MetaballsGltfVolume, RestPoseKeepsTheRestVolume) { gltf_volume::compare(0, 0); }
TEST(MetaballsGltfVolume, FingersFlexed60) { gltf_volume::compare(60, 60); }
TEST(MetaballsGltfVolume, FingersFlexed90) { gltf_volume::compare(90, 90); }
