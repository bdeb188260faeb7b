// Synergy chains (anatomically-based §3): one commanded rotation is spread
// over a chain of joints, "a 12 degree rotation of the thoracic region is
// interpreted as a one degree rotation at each thoracic vertebra". The
// chain's rotations sum to the command (the source keeps only its own
// share), its blob is major 2, and a coupling-only blob stays major 1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/toml_spec.hpp"
#include "sample_rig.hpp"
#include "sim_core/skeleton/pose.hpp"

namespace sinew::test {
namespace {

constexpr double kChainPi = 3.14159265358979323846;
constexpr int kVertebrae = 12;

// An input value for `degrees` (signed binary angle: 2^32 per turn).
int32_t chain_angle_input(double degrees) { return static_cast<int32_t>(std::llround(degrees / 360.0 * 4294967296.0)); }

// A thoracic spine: kVertebrae joints in a line, each with one flexion DOF
// about x, and the first vertebra's input spread over all of them.
rigc::RigSpec spine_spec(const std::vector<double>& weights) {
  rigc::RigSpec spec;
  for (int v = 0; v < kVertebrae; ++v) {
    rigc::JointSpec j;
    j.name = std::string(1, 't');  // appended, not "t" + ...: gcc 12's -Wrestrict misfires on that at -O3
    j.name += std::to_string(v + 1);
    j.parent = v - 1;
    j.translation = {0, v == 0 ? 0.0 : 0.025, 0};
    j.dofs = {{{1, 0, 0}, -60, 60}};
    spec.joints.push_back(j);
  }
  for (int v = 1; v < kVertebrae; ++v) {
    rigc::SynergySpec s;
    s.source_input = 0;
    s.target_joint = v;
    s.target_dof = 0;
    s.gain = weights[static_cast<size_t>(v)];
    s.share = true;
    spec.synergies.push_back(s);
  }
  return spec;
}

struct PosedChain {
  Blob blob;
  std::vector<uint64_t> arena;
  rig::Rig rig;
  std::vector<skeleton::LocalPose> locals;
  std::vector<fx::Mat34> model;
};

// Compiles and loads `spec`, then poses it with `inputs`.
void pose_chain(const rigc::RigSpec& spec, const std::vector<int32_t>& inputs, PosedChain* p,
                const std::vector<uint8_t>& measured = {}) {
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(rigc::compile_rig(spec, &bytes, &report, &error)) << error;
  p->blob = Blob(bytes);
  size_t arena_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(p->blob.data(), p->blob.size(), &arena_bytes);
  ASSERT_TRUE(st.ok()) << st.message;
  p->arena.assign(arena_bytes / 8 + 1, 0);
  st = rig::rig_init(p->blob.data(), p->blob.size(), p->arena.data(), p->arena.size() * 8, &p->rig);
  ASSERT_TRUE(st.ok()) << st.message;
  const size_t n = p->rig.joint_count();
  p->locals.resize(n);
  p->model.resize(n);
  std::vector<uint8_t> flags(n);
  ASSERT_GE(inputs.size(), p->rig.input_count);
  skeleton::dofs_to_locals(p->rig, inputs, measured, p->locals, flags);
  skeleton::locals_to_model(p->rig, p->locals, p->model);
}

// Rotation angle of a local pose's quaternion, in degrees (signed by its
// component along `axis`, 0 = x, 1 = y, 2 = z).
double local_angle_deg(const skeleton::LocalPose& l, int axis) {
  // q and -q are the same rotation: take the one with w >= 0 (angle in [-180, 180]).
  const double sign = l.rotation.w < 0 ? -1.0 : 1.0;
  const double c[3] = {static_cast<double>(l.rotation.x), static_cast<double>(l.rotation.y),
                       static_cast<double>(l.rotation.z)};
  return 2 * std::atan2(sign * c[axis], sign * static_cast<double>(l.rotation.w)) * 180 / kChainPi;
}

// Quaternion components are Q2.30: one rounding is 2^-30, about 1e-7 degrees
// of angle; a composed Mat34 (Q8.24 linear part) rounds at 2^-24 per
// product, 12 products stay below 1e-4 degrees.
constexpr double kLocalToleranceDeg = 1e-5;
constexpr double kModelToleranceDeg = 1e-4;

TEST(SynergyChain, TwelveDegreesGiveOneDegreePerVertebra) {
  PosedChain p;
  std::vector<int32_t> inputs(kVertebrae, 0);
  inputs[0] = chain_angle_input(12);
  pose_chain(spine_spec(std::vector<double>(kVertebrae, 1.0 / kVertebrae)), inputs, &p);
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_TRUE(p.rig.synergy_shares);
  double sum = 0;
  for (int v = 0; v < kVertebrae; ++v) {
    const double a = local_angle_deg(p.locals[static_cast<size_t>(v)], 0);
    EXPECT_NEAR(a, 1.0, kLocalToleranceDeg) << "vertebra " << v;
    sum += a;
  }
  // The chain's total is the command; the old additive rule gave the source
  // its full 12 degrees plus 11 shares: 23 degrees.
  EXPECT_NEAR(sum, 12.0, kVertebrae * kLocalToleranceDeg);
  const fx::Mat34& top = p.model[kVertebrae - 1];
  const double total = std::atan2(static_cast<double>(top.m[2][1]), static_cast<double>(top.m[1][1])) * 180 / kChainPi;
  std::printf("synergy chain: 12 deg over %d vertebrae -> top vertebra at %.6f deg (sum of locals %.6f)\n", kVertebrae,
              total, sum);
  EXPECT_NEAR(total, 12.0, kModelToleranceDeg);
}

// A measured DOF is the measurement: no synergy adds to it. Vertebra 5 is
// measured at 4 degrees while the chain is commanded 12: it stays at 4, the
// others take their 1 degree, and the source keeps the share it would have
// given vertebra 5 (2 degrees), so nothing is lost or counted twice. Without
// the rule vertebra 5 would read 5 degrees.
TEST(SynergyChain, AMeasuredVertebraKeepsItsAngleAndTheSourceItsShare) {
  PosedChain p;
  std::vector<int32_t> inputs(kVertebrae, 0);
  inputs[0] = chain_angle_input(12);
  inputs[5] = chain_angle_input(4);
  std::vector<uint8_t> measured(kVertebrae, 0);
  measured[5] = 1;
  pose_chain(spine_spec(std::vector<double>(kVertebrae, 1.0 / kVertebrae)), inputs, &p, measured);
  ASSERT_FALSE(HasFatalFailure());
  for (int v = 0; v < kVertebrae; ++v) {
    const double want = v == 5 ? 4.0 : (v == 0 ? 2.0 : 1.0);
    EXPECT_NEAR(local_angle_deg(p.locals[static_cast<size_t>(v)], 0), want, kLocalToleranceDeg) << "vertebra " << v;
  }
}

// The built-in hand couples each DIP to 2/3 of its PIP (the flexor tendons).
// A glove that measures the DIP must get the DIP it measured: with the index
// PIP at 60 and the DIP input at 30 degrees, an unmeasured DIP bends
// 30 + 40 = 70 degrees, a measured one 30.
TEST(SynergyChain, TheHandsDipCouplingNeverAddsToAMeasuredDip) {
  const rigc::RigSpec hand = rigc::builtin_hand();
  constexpr size_t kIndexPip = 2 + 4 * 1 + 2, kIndexDip = kIndexPip + 1, kIndexDipJoint = 1 + 3 * 1 + 2;
  ASSERT_EQ(hand.joints[kIndexDipJoint].name, "index_dip");
  for (const bool dip_measured : {false, true}) {
    PosedChain p;
    std::vector<int32_t> inputs(rigc::input_names(hand).size(), 0);
    inputs[kIndexPip] = chain_angle_input(60);
    inputs[kIndexDip] = chain_angle_input(30);
    std::vector<uint8_t> measured(inputs.size(), 0);
    measured[kIndexDip] = dip_measured ? 1 : 0;
    pose_chain(hand, inputs, &p, measured);
    ASSERT_FALSE(HasFatalFailure());
    EXPECT_NEAR(local_angle_deg(p.locals[kIndexDipJoint], 1), dip_measured ? 30.0 : 70.0, 1e-3)
        << (dip_measured ? "measured" : "unmeasured");
    EXPECT_NEAR(local_angle_deg(p.locals[kIndexDipJoint - 1], 1), 60.0, 1e-3) << "the PIP is its own input";
  }
}

TEST(SynergyChain, WeightsSplitTheCommandAndKeepItsSum) {
  // Lower vertebrae take more: the source keeps 1 - (the others' shares).
  std::vector<double> weights(kVertebrae);
  double others = 0;
  for (int v = 1; v < kVertebrae; ++v) others += weights[static_cast<size_t>(v)] = 0.01 * v;
  weights[0] = 1 - others;  // 0.34
  PosedChain p;
  std::vector<int32_t> inputs(kVertebrae, 0);
  inputs[0] = chain_angle_input(-30);
  pose_chain(spine_spec(weights), inputs, &p);
  ASSERT_FALSE(HasFatalFailure());
  double sum = 0;
  for (int v = 0; v < kVertebrae; ++v) {
    const double a = local_angle_deg(p.locals[static_cast<size_t>(v)], 0);
    EXPECT_NEAR(a, -30 * weights[static_cast<size_t>(v)], kLocalToleranceDeg) << "vertebra " << v;
    sum += a;
  }
  EXPECT_NEAR(sum, -30.0, kVertebrae * kLocalToleranceDeg);
}

TEST(SynergyChain, BlobMajorVersionSaysWhetherSharesArePresent) {
  // A coupling-only rig keeps major 1 (bytes unchanged for 1.x loaders);
  // one with a chain is major 2, which a 1.x loader refuses.
  EXPECT_EQ(compile_sample().header().version_major, rig::kVersionMajorFirst);
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(rigc::compile_rig(spine_spec(std::vector<double>(kVertebrae, 1.0 / kVertebrae)), &bytes, &report, &error))
      << error;
  EXPECT_EQ(Blob(bytes).header().version_major, rig::kVersionMajorShares);
}

TEST(SynergyChain, LoaderRefusesAnUnknownModeAndAShareAboveOne) {
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(rigc::compile_rig(spine_spec(std::vector<double>(kVertebrae, 1.0 / kVertebrae)), &bytes, &report, &error))
      << error;
  const auto refused = [&](size_t field, auto value, const char* name) {
    Blob b(bytes);
    b.write(b.section_offset(rig::kSectionSynergies) + field, value);
    b.reseal();
    size_t arena = 0;
    const rig::LoadStatus st = rig::rig_validate(b.data(), b.size(), &arena);
    EXPECT_EQ(st.error, rig::LoadError::kBadValue) << name;
    EXPECT_NE(std::string(st.message).find(name), std::string::npos) << st.message;
  };
  refused(5, uint8_t{2}, "mode");              // SynergyRecord::mode @5
  refused(8, int32_t{(1 << 30) + 1}, "gain");  // a share above 1
  refused(8, int32_t{-1}, "gain");             // a negative share
}

TEST(SynergyChain, CompilerRefusesSharesAboveTheCommand) {
  rigc::RigSpec spec = spine_spec(std::vector<double>(kVertebrae, 0.1));  // 11 x 0.1 > 1
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  EXPECT_FALSE(rigc::compile_rig(spec, &bytes, &report, &error));
  EXPECT_NE(error.find("shares sum above 1"), std::string::npos) << error;
}

// A spec in a fresh directory; returns rigc's error ("" when it loads).
std::string chain_spec_error(const std::string& text, rigc::RigSpec* out) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("sinew_synergy_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "chain.toml";
  std::ofstream(path) << text;
  std::string error;
  const bool ok = rigc::load_toml_spec(path.string(), out, &error);
  std::filesystem::remove_all(dir);
  return ok ? "" : error;
}

const char* const kHandHeader = "[rig]\nsource = \"builtin:hand\"\n";

TEST(SynergyChain, TomlChainSpreadsAFingerCurl) {
  // §3's hand: one curl command over the index finger's three flexions.
  rigc::RigSpec spec;
  const std::string text = std::string(kHandHeader) +
                           "[[synergy]]\nsource = \"index_mcp.0\"\n"
                           "chain = [\"index_mcp.0\", \"index_pip.0\", \"index_dip.0\"]\n"
                           "weights = [0.5, 0.3, 0.2]\n";
  ASSERT_EQ(chain_spec_error(text, &spec), "");
  PosedChain p;
  std::vector<int32_t> inputs(rigc::input_names(spec).size(), 0);
  const auto input = [&](const char* name) {
    const std::vector<std::string> names = rigc::input_names(spec);
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    ADD_FAILURE() << name;
    return size_t{0};
  };
  inputs[input("index_mcp.0")] = chain_angle_input(80);
  pose_chain(spec, inputs, &p);
  ASSERT_FALSE(HasFatalFailure());
  const double mcp = local_angle_deg(p.locals[static_cast<size_t>(rigc::joint_index(spec, "index_mcp"))], 1);
  const double pip = local_angle_deg(p.locals[static_cast<size_t>(rigc::joint_index(spec, "index_pip"))], 1);
  const double dip = local_angle_deg(p.locals[static_cast<size_t>(rigc::joint_index(spec, "index_dip"))], 1);
  std::printf("finger chain: 80 deg curl -> MCP %.5f, PIP %.5f, DIP %.5f deg\n", mcp, pip, dip);
  EXPECT_NEAR(mcp, 40.0, kLocalToleranceDeg);
  EXPECT_NEAR(pip, 24.0, kLocalToleranceDeg);
  // The built-in DIP coupling reads the PIP's own input (0 here), not its share.
  EXPECT_NEAR(dip, 16.0, kLocalToleranceDeg);
  EXPECT_NEAR(mcp + pip + dip, 80.0, 3 * kLocalToleranceDeg);
}

TEST(SynergyChain, TomlDefaultWeightsAreEqual) {
  rigc::RigSpec spec;
  const std::string text = std::string(kHandHeader) +
                           "[[synergy]]\nsource = \"ring_pip.0\"\n"
                           "chain = [\"ring_mcp.0\", \"ring_pip.0\", \"ring_dip.0\", \"middle_mcp.0\"]\n";
  ASSERT_EQ(chain_spec_error(text, &spec), "");
  const size_t builtin = rigc::builtin_hand().synergies.size();
  ASSERT_EQ(spec.synergies.size(), builtin + 3);  // the source keeps its own share
  for (size_t i = builtin; i < spec.synergies.size(); ++i) {
    EXPECT_TRUE(spec.synergies[i].share);
    EXPECT_DOUBLE_EQ(spec.synergies[i].gain, 0.25);
  }
}

TEST(SynergyChain, TomlErrorsNameTheLineAndKey) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchain = [\"index_mcp.0\", \"index_pip.0\"]\nweights = [0.5, 0.6]\n",
       ":6: [[synergy]] weights: must sum to 1"},
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchain = [\"index_pip.0\", \"index_dip.0\"]\n",
       ":5: [[synergy]] chain: must hold the source"},
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchain = [\"index_mcp.0\", \"index_nope.0\"]\n",
       ":5: [[synergy]] chain: no input named 'index_nope.0'"},
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchain = [\"index_mcp.0\", \"index_pip.0\"]\nweights = [1.0]\n",
       ":6: [[synergy]] weights: one number per chain input"},
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchain = [\"index_mcp.0\", \"index_pip.0\"]\nweights = [1.5, -0.5]\n",
       ":6: [[synergy]] weights: each in [0, 1]"},
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchain = [\"index_mcp.0\", \"index_pip.0\"]\ngain = 0.5\n",
       ":6: [[synergy]] gain: not with chain"},
      {"[[synergy]]\nsource = \"index_mcp.0\"\nchian = [\"index_mcp.0\"]\n", ":5: [[synergy]] chian: unknown key"},
  };
  for (const Case& c : cases) {
    rigc::RigSpec spec;
    const std::string error = chain_spec_error(std::string(kHandHeader) + c.text, &spec);
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.text << "\ngot: " << error;
  }
}

}  // namespace
}  // namespace sinew::test
