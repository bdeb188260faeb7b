#include "fixed_ops_workload.hpp"

#include "output_hash.hpp"
#include "sim_core/fixed/dual_quat.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "split_mix.hpp"

namespace sinew::determinism {

namespace fx = sinew::fx;

namespace {

void hash_vec(OutputHash& h, fx::Vec3 v) {
  h.add_i32(v.x);
  h.add_i32(v.y);
  h.add_i32(v.z);
}
void hash_quat(OutputHash& h, const fx::Quat& q) {
  h.add_i32(q.w);
  h.add_i32(q.x);
  h.add_i32(q.y);
  h.add_i32(q.z);
}

}  // namespace

uint64_t run_fixed_ops(int iterations) {
  SplitMix64 rng(0x5EED);
  OutputHash h;
  fx::Quat chain = fx::quat_identity();
  fx::Mat34 frame = fx::mat34_identity();
  for (int i = 0; i < iterations; ++i) {
    const fx::Angle a = rng.next_u32();
    const fx::SinCos sc = fx::sin_cos(a);
    h.add_i32(sc.sin);
    h.add_i32(sc.cos);
    h.add_u32(fx::atan2_angle(sc.sin, sc.cos));
    h.add_u32(fx::isqrt_u64(rng.next()));
    h.add_i32(fx::rsqrt_q60(rng.next() >> 1));
    fx::Vec3 axis;
    fx::normalize_to_unit({rng.next_i32(), rng.next_i32() >> 3, rng.next_i32() >> 7}, &axis);
    hash_vec(h, axis);
    const fx::Quat q = fx::quat_from_axis_angle(axis, a);
    chain = fx::mul(chain, q);
    if ((i & 15) == 0) fx::normalize(&chain);
    hash_quat(h, chain);
    const fx::Vec3 t{rng.range(-fx::kLenOne, fx::kLenOne), rng.range(-fx::kLenOne, fx::kLenOne),
                     rng.range(-fx::kLenOne, fx::kLenOne)};
    frame = fx::mul(frame, fx::mat34_from_quat(q, t));
    if ((i & 63) == 0) frame = fx::mat34_identity();
    const fx::Vec3 p{rng.range(-fx::kLenOne, fx::kLenOne), rng.range(-fx::kLenOne, fx::kLenOne), 0};
    hash_vec(h, fx::transform_point(frame, p));
    fx::DualQuat dq = fx::dual_quat_from_rt(chain, t);
    fx::normalize(&dq);
    hash_vec(h, fx::transform_point(dq, p));
    hash_quat(h, fx::nlerp(chain, q, static_cast<fx::Unit>(rng.next_u32() >> 2)));
  }
  return h.digest();
}

}  // namespace sinew::determinism
