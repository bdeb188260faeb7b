// Stage 3: position-based dynamics on the normal balls.
#include "jiggle_gains.hpp"
#include "kernels.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::metaballs::detail {
namespace {

// The swing and the coupling springs' pull are carried this many bits below
// the Len step (MetaballState::swing_fraction, swing_previous, ball_pull).
constexpr int kSwingFracBits = 24;
constexpr int64_t kSwingOne = int64_t{1} << kSwingFracBits;

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
//
// The swing is carried kSwingFracBits below the Len step (swing_fine,
// swing_previous) and rounded once into the centre: at 1 kHz the spring's
// k e and the damping's (1 - d)(e_n - e_{n-1}) are below 1/2 LSB for swings
// under a millimetre, and rounded every tick they would stall the swing
// there. A centre moved after the swing (action lines, per-step pairs)
// moves the carried swing by the same whole steps.
void swing_relative(MetaballState* s, uint32_t b) {
  const fx::Vec3 target = s->ball_target[b];
  // The gains at the state's tick rate (set_tick_rate; the model's at its own).
  const fx::Unit damping = s->jiggle_damping[b];
  const fx::Unit kept = fx::kUnitOne - s->jiggle_stiffness[b];
  const fx::Unit drive = static_cast<fx::Unit>(fx::isqrt_u64(static_cast<uint64_t>(int64_t{kept} * damping)));
  const fx::Vec3 e = fx::sub(s->ball_center[b], s->ball_last_target[b]);
  const fx::Vec3 step = fx::sub(target, s->ball_last_target[b]);
  const fx::Vec3 accel = fx::sub(step, s->ball_last_step[b]);
  const int32_t e3[3] = {e.x, e.y, e.z}, accel3[3] = {accel.x, accel.y, accel.z};
  const int32_t target3[3] = {target.x, target.y, target.z};
  int32_t centre[3];
  for (size_t i = 0; i < 3; ++i) {
    const size_t k = 3 * size_t{b} + i;
    // e_n: the centre's whole steps and the carried fraction; |e| < 2^32.
    const int64_t en = fx::add_sat_i64(int64_t{e3[i]} * kSwingOne, s->swing_fraction[k]);
    const int64_t en_1 = s->swing_previous[k];
    const int64_t inner = fx::add_sat_i64(en, fx::mul_shift_round(en - en_1, damping, fx::kUnitFracBits));
    const int64_t free = fx::mul_shift_round(inner, kept, fx::kUnitFracBits);
    // The coupling springs' pull enters as the bone's acceleration does.
    const int64_t pull = s->ball_pull.empty() ? 0 : s->ball_pull[k];
    const int64_t forced = fx::add_sat_i64(int64_t{accel3[i]} * kSwingOne, -pull);
    const int64_t next = fx::add_sat_i64(free, -fx::mul_shift_round(forced, drive, fx::kUnitFracBits));
    const int64_t whole = fx::round_shift(next, kSwingFracBits);
    centre[i] = fx::sat_i32(int64_t{target3[i]} + whole);
    s->swing_fraction[k] = next - whole * kSwingOne;  // in [-2^23, 2^23)
    s->swing_previous[k] = en;
  }
  s->ball_center[b] = {centre[0], centre[1], centre[2]};
  s->ball_last_target[b] = target;
  s->ball_last_step[b] = step;
}

// The pull h^2 F of the coupling springs (jiggle_gains.hpp) on each jiggle
// ball, from the centres at the start of the tick: F = -omega_c^2 C grad C
// with eq. (3)'s C = |c_a - c_b| - d, so each unit-mass jiggle ball of a
// pair takes x C along the pair (a kinematic ball does not move).
void coupling_pull(const MetaballModel& m, MetaballState* s) {
  for (int64_t& p : s->ball_pull) p = 0;
  for (size_t k = 0; k < m.pairs.size(); ++k) {
    const BallPair& p = m.pairs[k];
    const fx::Vec3 diff = fx::sub(s->ball_center[p.a], s->ball_center[p.b]);
    const uint64_t n2 = static_cast<uint64_t>(int64_t{diff.x} * diff.x) +
                        static_cast<uint64_t>(int64_t{diff.y} * diff.y) +
                        static_cast<uint64_t>(int64_t{diff.z} * diff.z);
    if (n2 == 0) {  // coincident balls: no direction to pull along
      ++s->stats.skipped_pairs;
      continue;
    }
    fx::Vec3 dir;
    fx::normalize_fast(diff, &dir);
    // x C kSwingFracBits below the Len step: |C| < 2^33, x < 2^31, so
    // |x C| < 2^(34 + kSwingFracBits) = 2^58 and each component and each
    // ball's sum (at most kMaxPairs terms, saturated) fit in int64.
    const int64_t c = int64_t{fx::isqrt_fast(n2)} - p.rest;
    const int64_t pull = fx::mul_shift_round(c, s->pair_coupling[k], fx::kUnitFracBits - kSwingFracBits);
    const int32_t d[3] = {dir.x, dir.y, dir.z};
    for (size_t i = 0; i < 3; ++i) {
      const int64_t f = fx::mul_shift_round(pull, d[i], fx::kUnitFracBits);
      if (m.ball_jiggle[p.a] != 0)
        s->ball_pull[3 * size_t{p.a} + i] = fx::add_sat_i64(s->ball_pull[3 * size_t{p.a} + i], -f);
      if (m.ball_jiggle[p.b] != 0)
        s->ball_pull[3 * size_t{p.b} + i] = fx::add_sat_i64(s->ball_pull[3 * size_t{p.b} + i], f);
    }
  }
}

}  // namespace

bool coupling_stable(const MetaballModel& m, MetaballState* s, uint32_t tick_hz) {
  if (m.jiggle_rate_hz == 0 || m.pairs.empty()) return true;
  // Gershgorin: the coupling matrix's largest eigenvalue is at most the
  // largest row sum, sum over a ball's pairs of 2 x (ball_pull.x is the
  // scratch). The recurrence e' = (1 - k)((1 + d) e - d e_) - r lambda e is
  // stable (Jury) while r lambda < (1 - k)(1 + d) + 1 + (1 - k) d.
  for (int64_t& p : s->ball_pull) p = 0;
  for (size_t k = 0; k < m.pairs.size(); ++k) {
    fx::Unit x = 0;
    if (!coupling_for_rate(m.pairs[k].stiffness, m.jiggle_rate_hz, tick_hz, &x)) return false;
    for (const uint16_t b : {m.pairs[k].a, m.pairs[k].b})
      if (m.ball_jiggle[b] != 0) s->ball_pull[3 * size_t{b}] += 2 * int64_t{x};  // < kMaxPairs 2^32
  }
  for (uint32_t b = 0; b < m.ball_count(); ++b) {
    if (m.ball_jiggle[b] == 0) continue;
    JiggleGains g;
    if (!jiggle_gains_for_rate({m.ball_jiggle[b], m.jiggle_damping}, m.jiggle_rate_hz, tick_hz, &g)) return false;
    const int64_t kept = fx::kUnitOne - g.stiffness;
    const int64_t r = fx::isqrt_u64(static_cast<uint64_t>(kept * g.damping));
    const int64_t limit =
        fx::round_shift(kept * (fx::kUnitOne + 2 * int64_t{g.damping}), fx::kUnitFracBits) + fx::kUnitOne;
    if (fx::mul_shift_round(r, s->ball_pull[3 * size_t{b}], fx::kUnitFracBits) >= limit) return false;
  }
  return true;
}

void solve_pbd(const MetaballModel& m, MetaballState* s) {
  const uint32_t nb = m.ball_count();
  const bool relative = m.jiggle_rate_hz != 0;
  // Physical jiggle's pairs are springs in the swing (coupling_pull), not
  // projections; with jiggle off the jiggle balls follow their centres alone.
  const bool coupled = !s->pair_coupling.empty();
  if (coupled) {
    s->stats.skipped_pairs = 0;
    if (s->primed && s->features.pbd && s->features.jiggle) coupling_pull(m, s);
  }
  for (uint32_t b = 0; b < nb; ++b) {
    const fx::Vec3 target = s->ball_target[b];
    const fx::Unit k = m.ball_jiggle[b];
    if (k == 0 || !s->primed || !s->features.pbd || !s->features.jiggle) {
      s->ball_previous[b] = relative ? fx::Vec3{0, 0, 0} : target;
      if (relative)
        for (size_t i = 0; i < 3; ++i) s->swing_fraction[3 * size_t{b} + i] = s->swing_previous[3 * size_t{b} + i] = 0;
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
  if (!coupled) s->stats.skipped_pairs = 0;
  if (!s->features.pbd) return;
  const bool actions = s->features.action_lines && !m.action_balls.empty();
  if (actions)
    for (size_t k = 0; k < m.action_balls.size(); ++k) s->action_point[k] = action_line_point(m, *s, m.action_balls[k]);
  const std::span<const BallPair> projected = coupled ? std::span<const BallPair>{} : m.pairs;
  for (uint32_t it = 0; it < m.pbd_iterations; ++it) {
    for (const BallPair& p : projected) s->stats.skipped_pairs += project(p, s->ball_center) ? 0u : 1u;
    if (actions)
      for (size_t k = 0; k < m.action_balls.size(); ++k)
        project_action(m.action_balls[k], s->action_point[k], s->ball_center);
  }
}

}  // namespace sinew::metaballs::detail
