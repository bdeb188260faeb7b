// Small bar-nets for the solver tests: a one-joint rig whose bones stay at
// identity (so skinned = rest), loads bound to two inputs that switch them
// on (angle 90) or off (0), and a double-precision oracle of eq. (4).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "host_tools/layers/barnet/net_spec.hpp"
#include "sim_core/barnet/barnet.hpp"

namespace sinew::test::barnet {

namespace lb = sinew::layers::barnet;
namespace bn = sinew::barnet;

inline rigc::RigSpec one_joint_rig() {
  rigc::RigSpec rig;
  rigc::JointSpec j;
  j.name = "root";
  j.dofs = {{{1, 0, 0}, -180, 180}, {{0, 1, 0}, -180, 180}};
  rig.joints.push_back(j);
  rig.palette.push_back({});
  return rig;
}

inline lb::NodeSpec node(double x, double y, double z, bool fixed) {
  lb::NodeSpec n;
  n.rest = {x, y, z};
  n.fixed = fixed;
  n.influences = {{0, 1.0}};
  return n;
}

class SyntheticNet {
 public:
  explicit SyntheticNet(const lb::NetSpec& spec) : rig_(one_joint_rig()) {
    if (!lb::build_barnet(spec, rig_, &build_, &error_)) return;
    model_ = build_.model();
    arena_.assign(bn::barnet_state_bytes(model_) / 8 + 1, 0);
    const bn::LayerStatus s = bn::barnet_init(model_, arena_.data(), arena_.size() * 8, &state_);
    if (!s.ok()) {
      error_ = s.message;
      return;
    }
    for (auto& o : out_) o.assign(model_.nodes.size(), 0);
    for (size_t c = 0; c < 3; ++c) {
      outputs_.node[c] = out_[c];
      outputs_.skin[c] = {};
    }
  }
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  const bn::BarnetModel& model() const { return model_; }
  bn::BarnetState& state() { return state_; }
  const lb::BarnetBuild& build() const { return build_; }
  int32_t exponent() const { return build_.length_exponent; }

  // One step with load set 0 and/or 1 switched on; returns node positions [c][node].
  std::vector<std::vector<int32_t>> step(bool set0, bool set1) {
    const int32_t on = 1 << 30;  // 90 degrees
    const int32_t angles[2] = {set0 ? on : 0, set1 ? on : 0};
    const fx::Mat34 bones[1] = {fx::mat34_identity()};
    last_ = bn::barnet_step(&state_, {bones, angles}, outputs_);
    return {out_[0], out_[1], out_[2]};
  }
  const bn::LayerStatus& last_status() const { return last_; }

  // Eq. (4) in double from the quantised model: D x = p - D_f x_f with
  // p = p0 + loads, p0 = D x0 + D_f x0_f the rest load (the bone is the
  // identity, so it is not turned) and x_f = rest; returns free-node
  // positions in Len units (not rounded) [c][free node].
  std::vector<std::vector<double>> oracle(bool set0, bool set1) const {
    const uint32_t n = state_.free_count;
    std::vector<std::vector<double>> result(3, std::vector<double>(n, 0));
    for (size_t c = 0; c < 3; ++c) {
      std::vector<double> a(n * n, 0), b(n, 0);
      auto rest = [this, c](uint32_t i) {
        const fx::Vec3 r = model_.nodes[i].rest;
        return static_cast<double>(c == 0 ? r.x : (c == 1 ? r.y : r.z));
      };
      for (const bn::BarRecord& bar : model_.bars) {
        const double q = std::ldexp(static_cast<double>(bar.q), -16);
        const double qd = q * (rest(bar.a) - rest(bar.b));
        if (bar.a < n) a[bar.a * n + bar.a] += q, b[bar.a] += qd;
        if (bar.b < n) a[bar.b * n + bar.b] += q, b[bar.b] -= qd;
        if (bar.a < n && bar.b < n) a[bar.a * n + bar.b] -= q, a[bar.b * n + bar.a] -= q;
        if (bar.a < n && bar.b >= n) b[bar.a] += q * rest(bar.b);
        if (bar.b < n && bar.a >= n) b[bar.b] += q * rest(bar.a);
      }
      for (const bn::LoadRecord& l : model_.loads) {
        if (!(l.input == 0 ? set0 : set1)) continue;
        const int32_t f = c == 0 ? l.force.x : (c == 1 ? l.force.y : l.force.z);
        b[l.node] += std::ldexp(static_cast<double>(f), -24 + 20);  // Force Q.24 -> Len-scaled force
      }
      // Gaussian elimination (D is SPD; no pivoting needed).
      for (uint32_t k = 0; k < n; ++k)
        for (uint32_t i = k + 1; i < n; ++i) {
          const double f = a[i * n + k] / a[k * n + k];
          if (f == 0) continue;
          for (uint32_t j = k; j < n; ++j) a[i * n + j] -= f * a[k * n + j];
          b[i] -= f * b[k];
        }
      for (uint32_t i = n; i-- > 0;) {
        double s = b[i];
        for (uint32_t j = i + 1; j < n; ++j) s -= a[i * n + j] * result[c][j];
        result[c][i] = s / a[i * n + i];
      }
    }
    return result;
  }

 private:
  rigc::RigSpec rig_;
  std::string error_;
  lb::BarnetBuild build_;
  bn::BarnetModel model_;
  std::vector<uint64_t> arena_;
  bn::BarnetState state_;
  std::vector<int32_t> out_[3];
  bn::StepOutputs outputs_;
  bn::LayerStatus last_;
};

}  // namespace sinew::test::barnet
