// Layer tables of rig specs (rigc): the committed specs compile every layer
// kind on the built-in rigs and on real glTF models (unnamed joints by node
// index, rest rotations and scales, a flat skeleton), the blob loads as the
// board loads it, and a table naming something the model cannot give is
// refused with the spec's line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/layers/builtin_layers.hpp"
#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/quantize.hpp"
#include "host_tools/rigc/toml_spec.hpp"
#include "sim_core/pipeline/layer_set.hpp"

namespace {

const std::string kSource = SINEW_SOURCE_DIR;

struct Compiled {
  std::vector<uint8_t> blob;
  std::vector<std::string> report;
  std::string error;
  bool ok = false;
};

Compiled compile_spec(const std::string& path) {
  Compiled c;
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs layers;
  sinew::rigc::CompileReport core;
  c.ok = sinew::rigc::load_toml_rig(path, &spec, &layers, &c.error) &&
         sinew::layers::add_layer_dofs(&spec, layers, &c.report, &c.error) &&
         sinew::rigc::compile_rig(spec, &c.blob, &core, &c.error) &&
         sinew::layers::compile_layers(spec, layers, &c.blob, &c.report, &c.error);
  return c;
}

struct Loaded {
  std::vector<uint64_t> blob, arena, layer_arena;
  sinew::rig::Rig rig;
  sinew::pipeline::LayerSet layers;
};

bool load(const std::vector<uint8_t>& bytes, Loaded* l, std::string* error) {
  l->blob.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(l->blob.data(), bytes.data(), bytes.size());
  const auto* p = reinterpret_cast<const uint8_t*>(l->blob.data());
  size_t a = 0, b = 0;
  sinew::rig::LoadStatus st = sinew::rig::rig_validate(p, bytes.size(), &a);
  l->arena.assign(a / 8 + 1, 0);
  if (st.ok()) st = sinew::rig::rig_init(p, bytes.size(), l->arena.data(), l->arena.size() * 8, &l->rig);
  if (st.ok()) st = sinew::pipeline::layers_validate(l->rig, p, bytes.size(), &b);
  l->layer_arena.assign(b / 8 + 1, 0);
  if (st.ok())
    st = sinew::pipeline::layers_init(l->rig, p, bytes.size(), l->layer_arena.data(), l->layer_arena.size() * 8,
                                      &l->layers);
  if (!st.ok()) *error = st.message;
  return st.ok();
}

std::string spec_error(const std::string& name, const std::string& text) {
  const std::string path = kSource + "/tests/data/" + name;  // beside the models its [rig] source names
  std::ofstream(path) << text;
  const Compiled c = compile_spec(path);
  std::remove(path.c_str());
  EXPECT_FALSE(c.ok) << name;
  return c.error;
}

// Compiles `text` as tests/data/<name> and loads it (the file is removed).
bool compile_text(const std::string& name, const std::string& text, Loaded* l, std::string* error) {
  const std::string path = kSource + "/tests/data/" + name;
  std::ofstream(path) << text;
  const Compiled c = compile_spec(path);
  std::remove(path.c_str());
  if (!c.ok) return *error = c.error, false;
  return load(c.blob, l, error);
}

const std::string kArmSkinTable =
    "[skin]                  # elastic skin over the muscle (LEMAN), in its support region\n";

// rigs/arm.toml with `keys` at the top of its [skin] table ("" if it has none).
std::string arm_spec_with_skin_keys(const std::string& keys) {
  std::ifstream in(kSource + "/rigs/arm.toml");
  std::string text, line;
  while (std::getline(in, line)) text += line + "\n";
  const size_t at = text.find(kArmSkinTable);
  if (at == std::string::npos) return "";
  return text.insert(at + kArmSkinTable.size(), keys);
}

}  // namespace

TEST(RigSpecs, CommittedSpecsCompileEveryLayerKind) {
  for (const char* spec : {"rigs/arm.toml", "rigs/hand.toml", "tests/data/rigged_figure_layers.toml",
                           "tests/data/generic_hand_layers.toml", "tests/data/rigged_simple_layers.toml",
                           "tests/data/generic_hand_dynamic_layers.toml"}) {
    const Compiled c = compile_spec(kSource + "/" + spec);
    ASSERT_TRUE(c.ok) << spec << ": " << c.error;
    Loaded l;
    std::string error;
    ASSERT_TRUE(load(c.blob, &l, &error)) << spec << ": " << error;
    std::printf("%s: %zu bytes, %u joints, %u vertices;", spec, c.blob.size(), l.rig.joint_count(),
                l.rig.vertex_count());
    for (const std::string& line : c.report) std::printf(" [%s]", line.c_str());
    std::printf("\n");
    EXPECT_EQ(l.layers.sph.count, 1u) << spec;
    EXPECT_TRUE(l.layers.metaballs.present) << spec;
    EXPECT_TRUE(l.layers.anatomy.has_muscles) << spec;
    EXPECT_TRUE(l.layers.anatomy.has_skin) << spec;
    EXPECT_EQ(l.layers.barnet.count, 1u) << spec;
    // The SPH joint's force input, and the dynamic skin's three base-acceleration inputs.
    const bool dynamic = std::string(spec).find("dynamic") != std::string::npos;
    EXPECT_EQ(l.layers.external_count(), dynamic ? 4u : 1u) << spec;
  }
}

// rigs/arm.toml is the built-in arm's commented spec: its layer sections
// are the ones the daemon embeds, byte for byte.
TEST(RigSpecs, ArmSpecGivesTheBuiltInLayers) {
  const Compiled spec = compile_spec(kSource + "/rigs/arm.toml");
  ASSERT_TRUE(spec.ok) << spec.error;
  std::vector<uint8_t> builtin;
  std::vector<std::string> report;
  std::string error;
  ASSERT_TRUE(sinew::layers::compile_builtin("arm", &builtin, &report, &error)) << error;
  const auto layer_sections = [](const std::vector<uint8_t>& b) {
    sinew::rig::FileHeader h;
    std::memcpy(&h, b.data(), sizeof(h));
    std::vector<std::vector<uint8_t>> out;
    for (uint32_t i = 0; i < h.section_count; ++i) {
      sinew::rig::SectionEntry e;
      std::memcpy(&e, b.data() + h.section_table_offset + i * sizeof(e), sizeof(e));
      if (i >= 11) out.emplace_back(b.begin() + e.offset, b.begin() + e.offset + e.size);  // after the core's 11
    }
    return out;
  };
  const auto a = layer_sections(spec.blob), b = layer_sections(builtin);
  ASSERT_EQ(a.size(), 6u);
  EXPECT_EQ(a, b);
}

TEST(RigSpecs, LayerTableErrorsNameTheLine) {
  const std::string arm = "[rig]\nsource = \"builtin:arm\"\n";
  const std::string figure = "[rig]\nsource = \"RiggedFigure.glb\"\n";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {arm + "[[sph]]\njont = \"elbow\"\n", ":4: [[sph]] jont: unknown key"},
      {arm + "[[sph]]\njoint = \"nope\"\n", ":4: [[sph]] joint: no joint named 'nope'"},
      {arm + "[[sph]]\njoint = \"shoulder\"\n", "'shoulder' is a root"},
      {arm + "[[sph]]\njoint = 2\n", "joint by node index needs a glTF source"},
      {figure + "[[barnet]]\njoint = 99\n", ":4: [[barnet]] joint: no joint of the rig comes from glTF node 99"},
      {arm + "[[sph]]\njoint = \"elbow\"\nparticles = 0\n", ":5: [[sph]] particles must be an integer in [8, 8192]"},
      {arm + "[[muscle]]\norigin = \"wrist\"\ninsertion = \"shoulder\"\n",
       "must be the insertion bone or one of its ancestors"},
      {arm + "[skin]\n", "[skin]: the elastic skin needs at least one [[muscle]]"},
      {arm + "[sphh]\n", ":3: sphh: unknown table"},
      {arm + "[metaballs]\nball_spacing = \"fine\"\n", "[metaballs] ball_spacing must be a finite number"},
      {"[rig]\nsource = \"builtin:arm\"\nrate_hz = 5\n", "[rig] rate_hz must be an integer in [13, 100000]"},
      {arm + "[[external_input]]\nname = \"grip\"\n", "name, unit, min and max are required"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const std::string error = spec_error("bad_layers_" + std::to_string(i++) + ".toml", c.text);
    EXPECT_NE(error.find(c.expected), std::string::npos) << "spec:\n" << c.text << "\ngot: " << error;
  }
}

// The committed fuzz seeds are what rigc makes today (a format change must
// regenerate them: rigc tests/data/rigged_simple_layers.toml -o ...).
TEST(RigSpecs, FuzzSeedsAreCurrent) {
  const Compiled c = compile_spec(kSource + "/tests/data/rigged_simple_layers.toml");
  ASSERT_TRUE(c.ok) << c.error;
  std::ifstream f(kSource + "/tests/fuzz/corpus/rig/rigged_simple_layers.rig", std::ios::binary);
  const std::vector<uint8_t> seed((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(seed, c.blob) << "regenerate tests/fuzz/corpus/rig/rigged_simple_layers.rig with rigc";
}

// The elastic skin's solver keys (docs/anatomy.md, "Dynamic mode") reach
// the loaded model, converted to rig units; a bad mode names the table.
TEST(RigSpecs, SkinSolverKeysReachTheLoadedModel) {
  const std::string text = arm_spec_with_skin_keys(
      "mode = \"dynamic\"\nvertex_mass = 0.02\nstiffness_scale = 40\nanchor_damping = 0.25\n"
      "band_damping = 0.125\nsubstep_hz = 2000\nmax_substeps = 8\nconstraint_passes = 2\n"
      "tolerance = 0.001\nfat = 0.002\ngravity = [0, -9.81, 0]\n");
  ASSERT_FALSE(text.empty());
  Loaded l;
  std::string error;
  ASSERT_TRUE(compile_text("skin_solver_keys.toml", text, &l, &error)) << error;
  ASSERT_TRUE(l.layers.anatomy.has_skin);
  const sinew::elastic_skin::SkinSolverParams& s = l.layers.anatomy.skin.solver;
  const int e = l.rig.length_exponent;  // one rig unit is 2^e model units
  EXPECT_EQ(s.mode, static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kDynamic));
  EXPECT_EQ(s.substep_hz, 2000u);
  EXPECT_EQ(s.max_substeps, 8u);
  EXPECT_EQ(s.constraint_passes, 2u);
  EXPECT_EQ(s.vertex_mass, std::lround(0.02 * 16777216.0));
  // The runtime measures length in rig units, time in s, mass in kg: its
  // stiffnesses and dampings carry the same numbers as N/m and N s/m, so
  // k / m = 40 N/m / 0.02 kg = 2000 /s^2 and c / m = 12.5 /s whatever the
  // rig unit (e = -8 here); only accelerations and lengths scale with it.
  ASSERT_NE(e, 0);
  EXPECT_EQ(s.stiffness_scale, std::lround(40.0 * 65536.0));
  EXPECT_EQ(s.anchor_damping, std::lround(0.25 * 65536.0));
  EXPECT_EQ(s.band_damping, std::lround(0.125 * 65536.0));
  // Within the two quantisations: 1/2 LSB of Q16.16 on 40 and of Q8.24 on 0.02.
  EXPECT_NEAR(static_cast<double>(s.stiffness_scale) / s.vertex_mass * 256.0, 40.0 / 0.02,
              2000 * (0.5 / (40 * 65536.0) + 0.5 / (0.02 * 16777216.0)));
  EXPECT_EQ(s.tolerance, std::lround(std::ldexp(0.001, 20 - e)));
  EXPECT_EQ(s.fat_thickness, std::lround(std::ldexp(0.002, 20 - e)));
  EXPECT_EQ(s.gravity.y, std::lround(std::ldexp(-9.81, 8 - e)));  // Q24.8
  EXPECT_EQ(s.gravity.x, 0);

  const std::string bad = spec_error("skin_bad_mode.toml",
                                     "[rig]\nsource = \"builtin:arm\"\n[[muscle]]\norigin = "
                                     "\"shoulder\"\ninsertion = \"elbow\"\n[skin]\nmode = "
                                     "\"wobbly\"\n");
  EXPECT_NE(bad.find("mode must be \"static\" or \"dynamic\""), std::string::npos) << bad;
}

// The muscle-shape keys of [[muscle]] (docs/anatomy.md, "Muscle shape"),
// the belly's Barr deformations and [skin] edge_damping reach the loaded
// model (a MUSC version 3 section); each out-of-range value is refused
// naming the table, the key and its range.
TEST(RigSpecs, MuscleShapeAndSkinKeysReachTheLoadedModel) {
  std::string text = arm_spec_with_skin_keys("mode = \"dynamic\"\nedge_damping = 0.25\nfat_normal = \"surface\"\n");
  const std::string insertion = "insertion = \"elbow\"\n";
  size_t at = text.find(insertion);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + insertion.size(),
              "end_axes = \"bone_normals\"\npivot = \"variable\"\nbelly_taper = 0.25\nbelly_twist = 30\n"
              "belly_bend = -10\n");
  at = text.find(kArmSkinTable);
  ASSERT_NE(at, std::string::npos);
  text.insert(at,
              "[[muscle.slice]]\nindex = 3\ntranslate = [0.001, 0, 0]\nrotate = [0, 0, 15]\n"
              "[[muscle.slice]]\nindex = 7\nrotate = [-20, 0, 0]\n\n");
  Loaded l;
  std::string error;
  ASSERT_TRUE(compile_text("muscle_shape_keys.toml", text, &l, &error)) << error;
  ASSERT_TRUE(l.layers.anatomy.has_muscles);
  const int e = l.rig.length_exponent;
  const sinew::muscle::MuscleModel& m = l.layers.anatomy.muscles;
  ASSERT_EQ(m.shapes.size(), 1u);
  const sinew::muscle::MuscleShape& sh = m.shapes[0];
  EXPECT_EQ(sh.end_axes, static_cast<uint8_t>(sinew::muscle::EndAxes::kBoneNormals));
  EXPECT_EQ(sh.pivot_mode, static_cast<uint8_t>(sinew::muscle::PivotMode::kVariable));
  EXPECT_GE(m.muscles[0].pivot_bone, 0);
  EXPECT_EQ(sh.slice[3].translate.x, sinew::rigc::to_len(0.001, e));
  EXPECT_EQ(sh.slice[3].translate.y, 0);
  // rotate = [0, 0, 15]: X turns to (cos 15, sin 15, 0) of the default frame.
  EXPECT_NEAR(std::ldexp(static_cast<double>(sh.slice[3].axis[0].x), -30), std::cos(15 * M_PI / 180), 1e-8);
  EXPECT_NEAR(std::ldexp(static_cast<double>(sh.slice[3].axis[0].y), -30), std::sin(15 * M_PI / 180), 1e-8);
  // rotate = [-20, 0, 0] on the end slice: Z turns to (0, sin 20, cos 20).
  EXPECT_NEAR(std::ldexp(static_cast<double>(sh.slice[7].axis[2].y), -30), std::sin(20 * M_PI / 180), 1e-8);
  EXPECT_EQ(sh.slice[7].axis[0].x, 1 << 30);
  for (const sinew::fx::Vec3& n : sh.end_normal) EXPECT_NE(n.x | n.y | n.z, 0);
  ASSERT_EQ(m.deformations.size(), m.primitives.size());
  EXPECT_EQ(m.deformations[0].taper, 1 << 28);                                  // 0.25 in Q2.30
  EXPECT_EQ(m.deformations[0].twist, static_cast<int32_t>(4294967296.0 / 12));  // 30 degrees
  EXPECT_EQ(m.deformations[0].bend, sinew::rigc::to_angle(-10));                // -10 degrees
  ASSERT_TRUE(l.layers.anatomy.has_skin);
  EXPECT_EQ(l.layers.anatomy.skin.solver.edge_damping, std::lround(0.25 * 65536.0));  // N s/m: no rig-unit factor
  EXPECT_EQ(l.layers.anatomy.skin.solver.fat_normal, static_cast<uint8_t>(sinew::elastic_skin::FatNormal::kSurface));
  EXPECT_EQ(l.layers.anatomy.skin.triangles.size(), l.rig.triangles.size());

  const std::string muscle =
      "[rig]\nsource = \"builtin:arm\"\n[[muscle]]\norigin = \"shoulder\"\ninsertion = "
      "\"elbow\"\n";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {muscle + "belly_taper = 0.7\n", "[[muscle]] belly_taper must be within [-0.5, 0.5]"},
      {muscle + "belly_twist = -120\n", "[[muscle]] belly_twist must be within [-90, 90] degrees"},
      {muscle + "belly_bend = 0.1\n", "[[muscle]] belly_bend must be 0 or of magnitude within [0.3515625, 90]"},
      {muscle + "end_axes = \"normals\"\n", "[[muscle]] end_axes must be \"path\" or \"bone_normals\""},
      {muscle + "pivot = \"sometimes\"\n", "[[muscle]] pivot must be \"off\", \"on\" or \"variable\""},
      {muscle + "[[muscle.slice]]\nindex = 8\n", "[[muscle.slice]] index must be an integer in [0, 7]"},
      {muscle + "[[muscle.slice]]\nrotate = [0, 0, 5]\n", "[[muscle.slice]] index is required"},
      {muscle + "[[muscle.slice]]\nindex = 2\nrotate = [0, 91, 0]\n",
       "[[muscle.slice]] rotate must be within [-90, 90] degrees"},
      {muscle + "[[muscle.slice]]\nindex = 0\ntranslate = [0, 0.001, 0]\n",
       "[[muscle.slice]] translate must be [0, 0, 0] for an end slice"},
      {muscle + "[[muscle.slice]]\nindex = 7\nrotate = [0, 10, 0]\n",
       "[[muscle.slice]] rotate must be [x, 0, 0] for an end slice"},
      {muscle + "[[muscle.slice]]\nindex = 2\nturn = [0, 1, 0]\n", "[[muscle.slice]] turn: unknown key"},
      {muscle + "[skin]\nedge_damping = -1\n", "[skin] edge_damping must be >= 0"},
      {muscle + "[skin]\nfat_normal = \"vertex\"\n", "[skin] fat_normal must be \"anchor\" or \"surface\""},
  };
  int i = 0;
  for (const Case& k : cases) {
    const std::string bad = spec_error("bad_shape_" + std::to_string(i++) + ".toml", k.text);
    EXPECT_NE(bad.find(k.expected), std::string::npos) << "spec:\n" << k.text << "\ngot: " << bad;
  }
}

// The belly's superquadric exponents of [[muscle]] (docs/anatomy.md):
// belly_exponent and belly_exponent_z reach the loaded model as a MUSC
// version 4 exponents pair (Q16.16), the record's exponent 0; an equal 2, 4
// or 8 stays on the record; out of [1, 16] is refused naming the table, the
// key and the range.
TEST(RigSpecs, MuscleBellyExponentsReachTheLoadedModel) {
  const std::string muscle =
      "[rig]\nsource = \"builtin:arm\"\n[[muscle]]\norigin = \"shoulder\"\ninsertion = "
      "\"elbow\"\n";
  const auto compiled = [&](const std::string& name, const std::string& keys, Loaded* l) {
    const std::string path = kSource + "/tests/data/" + name;
    std::ofstream(path) << muscle + keys;
    const Compiled c = compile_spec(path);
    std::remove(path.c_str());
    std::string error;
    const bool ok = c.ok && load(c.blob, l, &error);
    EXPECT_TRUE(ok) << c.error << error;
    return ok;
  };
  Loaded general;
  ASSERT_TRUE(compiled("belly_exponents.toml", "belly_exponent = 3.5\nbelly_exponent_z = 1.25\n", &general));
  const sinew::muscle::MuscleModel& m = general.layers.anatomy.muscles;
  ASSERT_EQ(m.exponents.size(), 1u);
  EXPECT_EQ(m.exponents[0].power_xy, 7 << 15);  // 3.5 in Q16.16
  EXPECT_EQ(m.exponents[0].power_z, 5 << 14);   // 1.25
  EXPECT_EQ(m.primitives[0].exponent, 0);
  Loaded same;  // belly_exponent_z defaults to belly_exponent
  ASSERT_TRUE(compiled("belly_exponent_only.toml", "belly_exponent = 6.5\n", &same));
  ASSERT_EQ(same.layers.anatomy.muscles.exponents.size(), 1u);
  EXPECT_EQ(same.layers.anatomy.muscles.exponents[0].power_z, 13 << 15);
  Loaded exact;  // an equal 8: the record's exponent, no exponents array (MUSC v1 to v3)
  ASSERT_TRUE(compiled("belly_exponent_8.toml", "belly_exponent = 8\n", &exact));
  EXPECT_TRUE(exact.layers.anatomy.muscles.exponents.empty());
  EXPECT_EQ(exact.layers.anatomy.muscles.primitives[0].exponent, 8);

  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {muscle + "belly_exponent = 0.5\n", "[[muscle]] belly_exponent must be within [1, 16]"},
      {muscle + "belly_exponent = 17\n", "[[muscle]] belly_exponent must be within [1, 16]"},
      {muscle + "belly_exponent_z = 0\n", "[[muscle]] belly_exponent_z must be within [1, 16]"},
      {muscle + "belly_exponent_z = 16.5\n", "[[muscle]] belly_exponent_z must be within [1, 16]"},
      {muscle + "belly_exponent = \"box\"\n", "[[muscle]] belly_exponent must be a finite number"},
  };
  int i = 0;
  for (const Case& k : cases) {
    const std::string bad = spec_error("bad_exponent_" + std::to_string(i++) + ".toml", k.text);
    EXPECT_NE(bad.find(k.expected), std::string::npos) << "spec:\n" << k.text << "\ngot: " << bad;
  }
}

// A dynamic [skin] without tissue keys gets them from the tissue
// (docs/anatomy.md, "Physical defaults"): the vertex mass from 3 kg/m^2 over
// the skin's area, the spring scale that makes a mean anchor swing at 10 Hz,
// the damping of a 0.3 damping ratio, and the lowest stable multiple of
// 1 kHz as the substep rate; a substep rate below the stiffest mode is
// refused naming the key.
TEST(RigSpecs, DynamicSkinTissueDefaultsFollowThePhysics) {
  const std::string dynamic = arm_spec_with_skin_keys("mode = \"dynamic\"\n");
  ASSERT_FALSE(dynamic.empty());
  Loaded l;
  std::string error;
  ASSERT_TRUE(compile_text("skin_tissue_defaults.toml", dynamic, &l, &error)) << error;
  const sinew::elastic_skin::SkinModel& m = l.layers.anatomy.skin;
  const sinew::elastic_skin::SkinSolverParams& s = m.solver;
  // The skin's area, model units (metres) squared, from the loaded rest mesh.
  const double unit = std::ldexp(1.0, l.rig.length_exponent - 20);
  double area = 0;
  for (size_t t = 0; t + 2 < l.rig.triangles.size(); t += 3) {
    double p[3][3];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) p[k][a] = l.rig.position[a][l.rig.triangles[t + static_cast<size_t>(k)]] * unit;
    const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    area += std::sqrt(std::pow(u[1] * v[2] - u[2] * v[1], 2) + std::pow(u[2] * v[0] - u[0] * v[2], 2) +
                      std::pow(u[0] * v[1] - u[1] * v[0], 2)) /
            2;
  }
  const double mass = s.vertex_mass / 16777216.0;
  // The rest mesh is the rig's, rounded to Q12.20: 1e-5 relative covers it.
  EXPECT_NEAR(mass, 3.0 * area / m.vertex_count, 1e-5 * mass + 0.5 / 16777216.0);
  double mean_ka = 0;
  for (uint32_t k : m.anchor_stiffness) mean_ka += k / 65536.0;
  mean_ka /= m.vertex_count;
  const double omega = 2 * M_PI * 10.0;
  const double scale = s.stiffness_scale / 65536.0, damping = s.anchor_damping / 65536.0;
  // Each within its own Q16.16 and the mass's Q8.24 rounding.
  EXPECT_NEAR(std::sqrt(mean_ka * scale / mass), omega, omega * (0.5 / s.stiffness_scale + 0.5 / s.vertex_mass + 1e-6));
  EXPECT_NEAR(damping, 2 * 0.3 * mass * omega, 0.5 / 65536.0 + 2 * 0.3 * omega * 0.5 / 16777216.0);
  EXPECT_EQ(s.band_damping, s.anchor_damping);
  // The runtime's Gershgorin bound of the stiffest mode, from the model.
  std::vector<double> row(m.vertex_count, 0);
  for (uint32_t v = 0; v < m.vertex_count; ++v) row[v] = m.anchor_stiffness[v] / 65536.0;
  for (const auto& e : m.edges) row[e.a] += 2 * e.k / 65536.0, row[e.b] += 2 * e.k / 65536.0;
  for (const auto& b : m.bands) row[b.vertex] += b.k / 65536.0;
  const double omega_max = std::sqrt(*std::max_element(row.begin(), row.end()) * scale / mass);
  EXPECT_GE(s.substep_hz, omega_max);           // stable: h omega_max <= 1
  EXPECT_LT(s.substep_hz - 1000.0, omega_max);  // and the lowest multiple of 1 kHz that is
  EXPECT_EQ(s.substep_hz % 1000, 0u);
  EXPECT_GE(s.max_substeps * 100u, s.substep_hz);  // a 100 Hz loop fits

  const std::string refused =
      spec_error("skin_slow_substeps.toml",
                 arm_spec_with_skin_keys("mode = \"dynamic\"\nintegrator = \"explicit\"\nsubstep_hz = 100\n"));
  EXPECT_NE(refused.find("[skin] substep_hz = 100 is too low for the skin's stiffest mode"), std::string::npos)
      << refused;
}

// [[rubber_band]] and [skin] fat_vertices (docs/anatomy.md): a band a spec
// names by its muscle point binds the skin vertex nearest that point, so the
// same band named by that vertex compiles to the same record; band = false
// drops a muscle's own fascia band; per-vertex fat replaces the derived
// thickness at exactly those vertices. Bad tables are refused naming the
// line and the key.
TEST(RigSpecs, RubberBandAndFatVertexTablesReachTheLoadedModel) {
  const std::string base = arm_spec_with_skin_keys("");
  ASSERT_FALSE(base.empty());
  Loaded plain;
  std::string error;
  ASSERT_TRUE(compile_text("bands_plain.toml", base, &plain, &error)) << error;
  const auto& bands0 = plain.layers.anatomy.skin.bands;
  ASSERT_EQ(bands0.size(), 1u);  // the biceps' own fascia band

  Loaded by_point;
  ASSERT_TRUE(compile_text("bands_by_point.toml",
                           base + "\n[[rubber_band]]\nmuscle = \"biceps\"\nslice = 2\nring_vertex = 1\nstiffness = 2\n",
                           &by_point, &error))
      << error;
  const auto& bands1 = by_point.layers.anatomy.skin.bands;
  ASSERT_EQ(bands1.size(), 2u);
  EXPECT_EQ(bands1[0].vertex, bands0[0].vertex);  // the default band is untouched
  EXPECT_EQ(bands1[1].muscle, 0u);
  EXPECT_EQ(bands1[1].k, 2 * 65536);
  EXPECT_NE(bands1[1].vertex, bands0[0].vertex);

  Loaded by_vertex;
  const std::string vertex = std::to_string(bands1[1].vertex);
  ASSERT_TRUE(compile_text("bands_by_vertex.toml",
                           base + "\n[[rubber_band]]\nmuscle = \"biceps\"\nvertex = " + vertex + "\nstiffness = 2\n",
                           &by_vertex, &error))
      << error;
  const auto& bands2 = by_vertex.layers.anatomy.skin.bands;
  ASSERT_EQ(bands2.size(), 2u);
  EXPECT_EQ(bands2[1].vertex, bands1[1].vertex);
  EXPECT_EQ(bands2[1].slice, bands1[1].slice);
  EXPECT_EQ(bands2[1].ring_vertex, bands1[1].ring_vertex);

  std::string no_default = base;
  const std::string name = "name = \"biceps\"\n";
  const size_t at = no_default.find(name);
  ASSERT_NE(at, std::string::npos);
  no_default.insert(at + name.size(), "band = false\n");
  Loaded none;
  ASSERT_TRUE(compile_text("bands_none.toml", no_default, &none, &error)) << error;
  EXPECT_TRUE(none.layers.anatomy.skin.bands.empty());

  // Fat: two vertices of the skin's region get their own thickness.
  const uint32_t v0 = bands0[0].vertex, v1 = bands1[1].vertex;
  Loaded fat;
  ASSERT_TRUE(compile_text("fat_vertices.toml",
                           arm_spec_with_skin_keys("fat_vertices = [[" + std::to_string(v0) + ", 0.0], [" +
                                                   std::to_string(v1) + ", 0.011]]\n"),
                           &fat, &error))
      << error;
  const auto& f0 = plain.layers.anatomy.skin.fat;
  const auto& f1 = fat.layers.anatomy.skin.fat;
  ASSERT_EQ(f0.size(), f1.size());
  ASSERT_GT(f0[v0], 0);
  const int e = fat.rig.length_exponent;
  for (size_t v = 0; v < f1.size(); ++v) {
    if (v == v0)
      EXPECT_EQ(f1[v], 0);
    else if (v == v1)
      EXPECT_EQ(f1[v], sinew::rigc::to_len(0.011, e));
    else
      ASSERT_EQ(f1[v], f0[v]) << "vertex " << v;
  }

  struct Case {
    std::string text, expected;
  };
  const std::string band = "\n[[rubber_band]]\n";
  const Case cases[] = {
      {base + band + "muscle = \"triceps\"\n", "[[rubber_band]]: muscle \"triceps\" is not a [[muscle]] name"},
      {base + band + "slice = 3\n", "[[rubber_band]] muscle must name a [[muscle]]"},
      {base + band + "muscle = \"biceps\"\nslice = 8\n", "[[rubber_band]] slice must be an integer in [0, 7]"},
      {base + band + "muscle = \"biceps\"\nring_vertex = 8\n",
       "[[rubber_band]]: ring_vertex 8 is beyond the muscles' 8 ring vertices"},
      {base + band + "muscle = \"biceps\"\nvertex = 99999999\n", "is beyond the mesh's"},
      {base + band + "muscle = \"biceps\"\nstiffness = 0\n", "[[rubber_band]] stiffness must be in (0, 256]"},
      {base + band + "muscle = \"biceps\"\nk = 1\n", "[[rubber_band]] k: unknown key"},
      {arm_spec_with_skin_keys("fat_vertices = [[1, -0.1]]\n"), "[skin] fat_vertices must be an array of"},
      {arm_spec_with_skin_keys("fat_vertices = [1, 0.1]\n"), "[skin] fat_vertices must be an array of"},
      {arm_spec_with_skin_keys("fat_vertices = [[99999999, 0.1]]\n"),
       "[skin]: fat_vertices: vertex 99999999 is beyond the mesh's"},
  };
  int i = 0;
  for (const Case& k : cases) {
    const std::string bad = spec_error("bad_band_" + std::to_string(i++) + ".toml", k.text);
    EXPECT_NE(bad.find(k.expected), std::string::npos) << "spec:\n" << k.text << "\ngot: " << bad;
  }
}
