#include "options.hpp"

#include <cmath>
#include <sstream>

#include "sim_core/metaballs/model.hpp"

namespace sinew::metaballs_build {
namespace {

bool in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

std::string region_problem(const char* kind, size_t i, const std::string& bone, double from, double to) {
  std::ostringstream s;
  if (bone.empty())
    s << kind << "[" << i << "].bone: empty";
  else if (!in(from, 0, 1) || !in(to, 0, 1) || from > to)
    s << kind << "[" << i << "].from/to: need 0 <= from <= to <= 1";
  return s.str();
}

}  // namespace

std::string check_options(const Options& o) {
  namespace mb = sinew::metaballs;
  if (!(o.ball_spacing > 0) || !std::isfinite(o.ball_spacing)) return "ball_spacing: must be a positive length";
  if (o.target_ball_count < 0 || o.target_ball_count > static_cast<int>(mb::kMaxBalls))
    return "target_ball_count: must be in [0, 4096]";
  if (o.weight_power < 1 || o.weight_power > 64) return "weight_power: must be in [1, 64]";
  if (!in(o.pair_reach, 0, 4)) return "pair_reach: must be in [0, 4]";
  if (!in(o.stretch_stiffness, 0, 1)) return "stretch_stiffness: must be in [0, 1]";
  if (o.pbd_iterations < 0 || o.pbd_iterations > static_cast<int>(mb::kMaxPbdIterations))
    return "pbd_iterations: must be in [0, 16]";
  if (!in(o.jiggle_damping, 0, 0.999)) return "jiggle_damping: must be in [0, 1)";
  if (!in(o.jiggle_stretch_stiffness, 0, 1)) return "jiggle_stretch_stiffness: must be in [0, 1]";
  if (!in(o.jiggle_frequency, 0, 1000)) return "jiggle_frequency: must be in [0, 1000] Hz";
  if (o.jiggle_frequency > 0 && !in(o.jiggle_window, 0.001, 1000)) return "jiggle_window: must be in [0.001, 1000] s";
  if (o.rate_hz == 0) return "rate_hz: must be > 0";
  if (o.jiggle_frequency > 0 && !in(o.jiggle_coupling, 0, static_cast<double>(o.rate_hz) / (2 * 3.14159265358979)))
    return "jiggle_coupling: must be in [0, rate_hz / (2 pi)] Hz";
  for (size_t i = 0; i < o.jiggle.size(); ++i) {
    const JiggleRegion& r = o.jiggle[i];
    if (std::string p = region_problem("jiggle", i, r.bone, r.from, r.to); !p.empty()) return p;
    if (!(r.stiffness > 0) || !in(r.stiffness, 0, 1))
      return "jiggle[" + std::to_string(i) + "].stiffness: must be in (0, 1]";
  }
  for (size_t i = 0; i < o.bulge.size(); ++i) {
    const BulgeRegion& r = o.bulge[i];
    if (std::string p = region_problem("bulge", i, r.bone, r.from, r.to); !p.empty()) return p;
    if (r.angle_a.empty() || r.angle_b.empty() || r.angle_a == r.angle_b)
      return "bulge[" + std::to_string(i) + "].angle_a/angle_b: need two different bones";
    if (!in(r.gain, 0, 0.999)) return "bulge[" + std::to_string(i) + "].gain: must be in [0, 1)";
  }
  for (size_t i = 0; i < o.action_lines.size(); ++i) {
    const ActionLineSpec& l = o.action_lines[i];
    const std::string n = "action_lines[" + std::to_string(i) + "]";
    if (l.origin.empty() || l.insertion.empty()) return n + ".origin/insertion: need two bones";
    if (!in(l.origin_at, 0, 1) || !in(l.insertion_at, 0, 1)) return n + ".origin_at/insertion_at: must be in [0, 1]";
    for (double x : l.side)
      if (!std::isfinite(x)) return n + ".side: must be finite";
    if (!(l.reach > 0) || !std::isfinite(l.reach)) return n + ".reach: must be a positive length";
    if (!in(l.stiffness, 0, 1)) return n + ".stiffness: must be in [0, 1]";
  }
  if (o.action_lines.size() > mb::kMaxActionLines) return "action_lines: more than 256";
  if (!(o.joint_inner >= 0) || !(o.joint_outer > o.joint_inner) || !std::isfinite(o.joint_outer))
    return "joint_inner/joint_outer: need 0 <= joint_inner < joint_outer";
  if (o.smoothing_passes < 0 || o.smoothing_passes > static_cast<int>(mb::kMaxSmoothingPasses))
    return "smoothing_passes: must be in [0, 8]";
  if (!in(o.smoothing_rate, 0, 1)) return "smoothing_rate: must be in [0, 1]";
  if (!in(o.overlap_reach, 0, 100)) return "overlap_reach: must be in [0, 100]";
  return {};
}

}  // namespace sinew::metaballs_build
