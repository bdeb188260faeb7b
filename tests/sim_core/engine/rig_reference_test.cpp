// The fixed-point engine against an independent double-precision (Eigen)
// implementation of the same rig: forward kinematics with synergies and
// limits, then LBS or DQS, over many random poses of the built-in rigs.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>

#include "rig_fixture.hpp"

using sinew::test::LoadedRig;
namespace rigc = sinew::rigc;

namespace {

using Affine = Eigen::Transform<double, 3, Eigen::Affine>;

// Model-space joint transforms of `spec` for DOF inputs in degrees.
std::vector<Affine> reference_fk(const rigc::RigSpec& spec, const std::vector<double>& input_deg) {
  std::vector<Affine> model(spec.joints.size());
  size_t first_input = 0;
  std::vector<size_t> first(spec.joints.size());
  for (size_t j = 0; j < spec.joints.size(); ++j) {
    first[j] = first_input;
    first_input += spec.joints[j].dofs.size();
  }
  for (size_t j = 0; j < spec.joints.size(); ++j) {
    const rigc::JointSpec& js = spec.joints[j];
    Eigen::Quaterniond rest(js.rotation[0], js.rotation[1], js.rotation[2], js.rotation[3]);
    Eigen::Quaterniond dof = Eigen::Quaterniond::Identity();
    for (size_t d = 0; d < js.dofs.size(); ++d) {
      double a = input_deg[first[j] + d];
      for (const rigc::SynergySpec& s : spec.synergies) {
        const double amount = s.gain * input_deg[static_cast<size_t>(s.source_input)];
        if (static_cast<size_t>(s.target_joint) == j && static_cast<size_t>(s.target_dof) == d) a += amount;
        if (s.share && static_cast<size_t>(s.source_input) == first[j] + d) a -= amount;  // a chain's share
      }
      a = std::clamp(a, js.dofs[d].min, js.dofs[d].max);
      const Eigen::Vector3d axis(js.dofs[d].axis[0], js.dofs[d].axis[1], js.dofs[d].axis[2]);
      dof = dof * Eigen::Quaterniond(Eigen::AngleAxisd(a * M_PI / 180, axis.normalized()));
    }
    Affine local = Affine::Identity();
    local.translate(Eigen::Vector3d(js.translation[0], js.translation[1], js.translation[2]));
    local.rotate(rest * dof);
    local.scale(Eigen::Vector3d(js.scale[0], js.scale[1], js.scale[2]));
    model[j] = js.parent < 0 ? local : model[static_cast<size_t>(js.parent)] * local;
  }
  return model;
}

Eigen::Vector3d reference_vertex(const rigc::RigSpec& spec, const std::vector<Affine>& model, size_t v, bool dual) {
  const rigc::VertexSpec& vs = spec.vertices[v];
  const Eigen::Vector3d p(vs.position[0], vs.position[1], vs.position[2]);
  double total = 0;
  for (const auto& in : vs.influences) total += in.weight;
  if (!dual) {
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (const auto& in : vs.influences) {
      const rigc::PaletteSpec& ps = spec.palette[static_cast<size_t>(in.palette)];
      Affine ibm;
      ibm.matrix() = Eigen::Map<const Eigen::Matrix4d>(ps.inverse_bind.data());
      out += in.weight / total * (model[static_cast<size_t>(ps.joint)] * ibm * p);
    }
    return out;
  }
  // DQS (Kavan et al.): blend (q, 0.5 t q) on the first influence's hemisphere.
  Eigen::Vector4d real = Eigen::Vector4d::Zero(), du = Eigen::Vector4d::Zero();
  Eigen::Quaterniond pivot;
  for (size_t k = 0; k < vs.influences.size(); ++k) {
    const rigc::PaletteSpec& ps = spec.palette[static_cast<size_t>(vs.influences[k].palette)];
    Affine ibm;
    ibm.matrix() = Eigen::Map<const Eigen::Matrix4d>(ps.inverse_bind.data());
    const Affine s = model[static_cast<size_t>(ps.joint)] * ibm;
    const Eigen::Quaterniond q(s.rotation());
    if (k == 0) pivot = q;
    const double w = vs.influences[k].weight / total * (pivot.dot(q) < 0 ? -1 : 1);
    const Eigen::Quaterniond t(0, s.translation().x(), s.translation().y(), s.translation().z());
    const Eigen::Quaterniond d = t * q;
    real += w * Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
    du += w * 0.5 * Eigen::Vector4d(d.w(), d.x(), d.y(), d.z());
  }
  const double n = real.norm();
  const Eigen::Quaterniond r(real[0] / n, real[1] / n, real[2] / n, real[3] / n);
  const Eigen::Quaterniond d(du[0] / n, du[1] / n, du[2] / n, du[3] / n);
  const Eigen::Quaterniond t2 = d * r.conjugate();
  return r * p + 2 * Eigen::Vector3d(t2.x(), t2.y(), t2.z());
}

void compare(const rigc::RigSpec& spec, bool dual, const char* label) {
  LoadedRig rig(spec);
  ASSERT_TRUE(rig.ok());
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> angle(-160, 160);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const auto& v : spec.vertices)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], v.position[static_cast<size_t>(c)]);
      hi[c] = std::max(hi[c], v.position[static_cast<size_t>(c)]);
    }
  const double diagonal = (hi - lo).norm();
  double worst = 0;
  for (int pose = 0; pose < 50; ++pose) {
    std::vector<double> deg(rig.inputs().size());
    for (size_t i = 0; i < deg.size(); ++i) {
      deg[i] = angle(rng);
      rig.inputs()[i] = sinew::test::degrees(deg[i]);
      deg[i] = static_cast<double>(rig.inputs()[i]) * 360.0 / 4294967296.0;  // the quantised command
    }
    ASSERT_TRUE(rig.step());
    const std::vector<Affine> model = reference_fk(spec, deg);
    for (size_t v = 0; v < spec.vertices.size(); v += 7) {
      const Eigen::Vector3d ref = reference_vertex(spec, model, v, dual);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::fabs(rig.position(c, static_cast<uint32_t>(v)) - ref[c]));
    }
  }
  std::printf("reference: %s, 50 random poses, max position error %.3g m = %.3g of the bbox diagonal\n", label, worst,
              worst / diagonal);
  EXPECT_LT(worst / diagonal, 2e-5);
}

}  // namespace

TEST(RigReference, ArmLbsMatchesDouble) { compare(rigc::builtin_arm(rigc::SkinChoice::kLinear), false, "arm LBS"); }
TEST(RigReference, ArmDqsMatchesDouble) {
  compare(rigc::builtin_arm(rigc::SkinChoice::kDualQuaternion), true, "arm DQS");
}
TEST(RigReference, HandDqsMatchesDouble) {
  compare(rigc::builtin_hand(rigc::SkinChoice::kDualQuaternion), true, "hand DQS");
}
