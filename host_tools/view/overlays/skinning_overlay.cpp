#include "skinning_overlay.hpp"

namespace sinew::view {

void ViewOverlay<pipeline::Stage::kSkinning>::add(const pipeline::Pipeline& p, int32_t e, OverlayArrays* a, JsonText&) {
  const rig::Rig& rig = *p.rig;
  a->add("joints", 3 * rig.joint_count());
  for (uint32_t k = 0; k < rig.joint_count(); ++k)
    for (int c = 0; c < 3; ++c) a->push(metres(p.engine.model[k].t[c], e));
}

}  // namespace sinew::view
