// Stage 3: position-based dynamics on the normal balls.
#include "kernels.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"

namespace sinew::metaballs::detail {
namespace {

// Projects one stretch constraint, eq. (3): C = |c_a - c_b| - d, moving each
// ball along the pair's direction by its share of stiffness * C.
bool project(const BallPair& p, std::span<fx::Vec3> c) {
  fx::Vec3& a = c[p.a];
  fx::Vec3& b = c[p.b];
  const fx::Vec3 diff = fx::sub(a, b);  // saturating: |component| < 2^31, squares < 2^62
  const uint64_t n2 = static_cast<uint64_t>(int64_t{diff.x} * diff.x) +
                      static_cast<uint64_t>(int64_t{diff.y} * diff.y) + static_cast<uint64_t>(int64_t{diff.z} * diff.z);
  if (n2 == 0) return false;  // coincident balls: no direction to push along
  const int64_t len = fx::isqrt_fast(n2);
  fx::Vec3 dir;
  fx::normalize_fast(diff, &dir);
  // |len - d| < 2^33 and stiffness <= 2^30: the product fits; the Len result is
  // saturated.
  const int64_t correction = fx::sat_i32(fx::round_shift((len - p.rest) * p.stiffness, fx::kUnitFracBits));
  const auto move = [&](fx::Unit share, int32_t d) {
    return fx::sat_i32(fx::round_shift(fx::round_shift(correction * share, fx::kUnitFracBits) * d, fx::kUnitFracBits));
  };
  a = fx::sub(a, {move(p.share_a, dir.x), move(p.share_a, dir.y), move(p.share_a, dir.z)});
  b = fx::add(b, {move(p.share_b, dir.x), move(p.share_b, dir.y), move(p.share_b, dir.z)});
  return true;
}

// The point of its action line an action ball keeps its distance from:
// L = O + along (I - O), the ends carried by their bones.
fx::Vec3 action_line_point(const MetaballModel& m, const MetaballState& s, const ActionBall& a) {
  const ActionLine& line = m.action_lines[a.line];
  const fx::Vec3 o = fx::transform_point(s.bone[line.origin_bone], line.origin_rest);
  const fx::Vec3 i = fx::transform_point(s.bone[line.insertion_bone], line.insertion_rest);
  return fx::add(o, fx::scale(fx::sub(i, o), a.along));
}

// Keeps a ball at its rest distance from its action line's point: C =
// |c - L| - rest, the ball moved along (c - L) by stiffness * C.
void project_action(const ActionBall& a, fx::Vec3 point, std::span<fx::Vec3> c) {
  fx::Vec3& ball = c[a.ball];
  const fx::Vec3 diff = fx::sub(ball, point);
  const uint64_t n2 = static_cast<uint64_t>(int64_t{diff.x} * diff.x) +
                      static_cast<uint64_t>(int64_t{diff.y} * diff.y) + static_cast<uint64_t>(int64_t{diff.z} * diff.z);
  if (n2 == 0) return;  // on the line: no direction to push along
  fx::Vec3 dir;
  fx::normalize_fast(diff, &dir);
  const int64_t correction =
      fx::sat_i32(fx::round_shift((int64_t{fx::isqrt_fast(n2)} - a.rest) * a.stiffness, fx::kUnitFracBits));
  const auto move = [&](int32_t d) { return fx::sat_i32(fx::round_shift(correction * d, fx::kUnitFracBits)); };
  ball = fx::sub(ball, {move(dir.x), move(dir.y), move(dir.z)});
}

// Secondary deformation in physical units (jiggle_gains.hpp): the swing
// e = c - c_target of a jiggle ball follows
//   e_{n+1} = (1 - k) ((1 + d) e_n - d e_{n-1}) - g (T_{n+1} - 2 T_n + T_{n-1}),
// the damped oscillator e'' + 2 sigma e' + omega0^2 e = -T'' sampled at each
// tick: the free swing is exact, and with g = r = sqrt((1 - k) d) a sudden
// change of the bone's velocity starts the swing of the continuous impulse
// response to within theta / sin(theta) (second order in dt).
void swing_relative(MetaballState* s, uint32_t b) {
  const fx::Vec3 target = s->ball_target[b];
  // The gains at the state's tick rate (set_tick_rate; the model's at its own).
  const fx::Unit damping = s->jiggle_damping[b];
  const fx::Unit kept = fx::kUnitOne - s->jiggle_stiffness[b];
  const fx::Unit drive = static_cast<fx::Unit>(fx::isqrt_u64(static_cast<uint64_t>(int64_t{kept} * damping)));
  const fx::Vec3 e = fx::sub(s->ball_center[b], s->ball_last_target[b]);
  const fx::Vec3 e_previous = s->ball_previous[b];
  const fx::Vec3 step = fx::sub(target, s->ball_last_target[b]);
  const fx::Vec3 accel = fx::sub(step, s->ball_last_step[b]);
  const fx::Vec3 free = fx::scale(fx::add(e, fx::scale(fx::sub(e, e_previous), damping)), kept);
  s->ball_previous[b] = e;
  s->ball_center[b] = fx::add(target, fx::sub(free, fx::scale(accel, drive)));
  s->ball_last_target[b] = target;
  s->ball_last_step[b] = step;
}

}  // namespace

void solve_pbd(const MetaballModel& m, MetaballState* s) {
  const uint32_t nb = m.ball_count();
  const bool relative = m.jiggle_rate_hz != 0;
  for (uint32_t b = 0; b < nb; ++b) {
    const fx::Vec3 target = s->ball_target[b];
    const fx::Unit k = m.ball_jiggle[b];
    if (k == 0 || !s->primed || !s->features.pbd || !s->features.jiggle) {
      s->ball_previous[b] = relative ? fx::Vec3{0, 0, 0} : target;
      s->ball_center[b] = target;
      s->ball_last_target[b] = target;
      s->ball_last_step[b] = {0, 0, 0};
      continue;
    }
    if (relative) {
      swing_relative(s, b);
      continue;
    }
    // Secondary deformation: damped Verlet prediction p = x + damping (x -
    // x_prev), then the spring to the kinematic centre as a PBD constraint of
    // stiffness k (softer springs lag and swing farther).
    const fx::Vec3 x = s->ball_center[b];
    const fx::Vec3 velocity = fx::scale(fx::sub(x, s->ball_previous[b]), m.jiggle_damping);
    const fx::Vec3 predicted = fx::add(x, velocity);
    s->ball_previous[b] = x;
    s->ball_center[b] = fx::add(predicted, fx::scale(fx::sub(target, predicted), k));
  }
  s->primed = true;
  s->stats.skipped_pairs = 0;
  if (!s->features.pbd) return;
  const bool actions = s->features.action_lines && !m.action_balls.empty();
  if (actions)
    for (size_t k = 0; k < m.action_balls.size(); ++k) s->action_point[k] = action_line_point(m, *s, m.action_balls[k]);
  for (uint32_t it = 0; it < m.pbd_iterations; ++it) {
    for (const BallPair& p : m.pairs) s->stats.skipped_pairs += project(p, s->ball_center) ? 0u : 1u;
    if (actions)
      for (size_t k = 0; k < m.action_balls.size(); ++k)
        project_action(m.action_balls[k], s->action_point[k], s->ball_center);
  }
}

}  // namespace sinew::metaballs::detail
