#include "sph_overlay.hpp"

namespace sinew::view {

// Every joint's particles, concatenated: position, pressure rho - rho0 in
// normalised density units (Q8.24), yielded 0/1; and per joint, its distal
// joint and whether it yielded.
void ViewOverlay<pipeline::Stage::kSph>::add(const pipeline::Pipeline& p, int32_t e, OverlayArrays* a, JsonText& j) {
  size_t particles = 0;
  for (uint32_t s = 0; s < p.sph.count; ++s) particles += p.sph.joint[s].pressure.size();
  a->add("sph_position", 3 * particles);
  for (uint32_t s = 0; s < p.sph.count; ++s)
    for (size_t k = 0; k < p.sph.joint[s].pressure.size(); ++k)
      for (int c = 0; c < 3; ++c) a->push(metres(p.sph.joint[s].position[c][k], e));
  a->add("sph_pressure", particles);
  for (uint32_t s = 0; s < p.sph.count; ++s)
    for (const auto d : p.sph.joint[s].pressure) a->push(std::ldexp(static_cast<double>(d), -24));
  a->add("sph_yielded", particles);
  for (uint32_t s = 0; s < p.sph.count; ++s)
    for (const uint8_t y : p.sph.joint[s].yielded) a->push(y);
  j.key("sph_joints").open_array();
  for (uint32_t s = 0; s < p.sph.count; ++s) {
    j.open_object();
    j.key("joint").number(p.sph.model[s].joint.distal_joint);
    j.key("yielded").boolean(p.sph.joint[s].joint_yielded);
    j.key("yielded_particles").number(p.sph.joint[s].yielded_particles);
    j.close_object();
  }
  j.close_array();
}

}  // namespace sinew::view
