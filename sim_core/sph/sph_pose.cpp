#include "sph_pose.hpp"

namespace sinew::sph {

bool joint_frame(const SphModel& m, std::span<const fx::Mat34> transforms, JointFrame* out) {
  if (m.joint.proximal_joint >= transforms.size() || m.joint.distal_joint >= transforms.size()) return false;
  out->proximal = &transforms[m.joint.proximal_joint];
  out->distal = &transforms[m.joint.distal_joint];
  out->centre = {out->distal->t[0], out->distal->t[1], out->distal->t[2]};
  // The linear part may carry scale (Q8.24); renormalise the axis.
  const fx::Vec3 a = fx::transform_vector(*out->distal, m.joint.axis);
  if (!fx::normalize_to_unit(a, &out->axis)) out->axis = m.joint.axis;
  return true;
}

void compute_ideal(SphState* st, const JointFrame& f) {
  const SphModel& m = *st->model;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    const fx::Mat34& M = m.bone[i] == static_cast<uint8_t>(Bone::kDistal) ? *f.distal : *f.proximal;
    const fx::Vec3 p = fx::transform_point(M, {m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]});
    st->ideal[0][i] = p.x;
    st->ideal[1][i] = p.y;
    st->ideal[2][i] = p.z;
  }
}

}  // namespace sinew::sph
