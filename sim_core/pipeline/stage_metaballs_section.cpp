// The metaballs stage's rig section: MBAL, at most one, loaded into the
// layer set (sim_core/metaballs/metaballs_section.hpp describes the record).
#include "sim_core/metaballs/validate.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {
namespace {

using rig::LoadError;
using rig::LoadStatus;

constexpr auto mb_array = [](std::string_view n) { return layer::array_ref(metaballs::kMetaballsSectionArrays, n); };

LoadStatus load_section(const SectionView& v, const rig::Rig& rig, metaballs::MetaballModel* out) {
  const metaballs::MetaballsSectionParams p = params_of<metaballs::MetaballsSectionParams>(v);
  metaballs::MetaballModel& m = *out;
  m.joint_count = p.joint_count;
  m.vertex_count = p.vertex_count;
  m.pbd_iterations = p.pbd_iterations;
  m.jiggle_damping = p.jiggle_damping;
  m.jiggle_rate_hz = v.header.rate_hz;  // > 0: physical jiggle gains built for this rate
  m.smoothing_passes = p.smoothing_passes;
  m.smoothing_rate = p.smoothing_rate;
  m.inverse_bind = named<fx::Mat34, mb_array("inverse_bind")>(v);
  m.ball_rest = named<fx::Vec3, mb_array("ball_rest")>(v);
  m.ball_radius = named<fx::Len, mb_array("ball_radius")>(v);
  m.ball_bone = named<uint16_t, mb_array("ball_bone")>(v);
  m.ball_joint = named<uint16_t, mb_array("ball_joint")>(v);
  m.ball_weight = named<fx::Unit, mb_array("ball_weight")>(v);
  m.ball_jiggle = named<fx::Unit, mb_array("ball_jiggle")>(v);
  m.pairs = named<metaballs::BallPair, mb_array("pairs")>(v);
  m.bulges = named<metaballs::BulgeRecord, mb_array("bulges")>(v);
  m.vertex_ball = named<uint16_t, mb_array("vertex_ball")>(v);
  m.vertex_weight = named<fx::Unit, mb_array("vertex_weight")>(v);
  m.vertex_disp = named<fx::Vec3, mb_array("vertex_disp")>(v);
  m.joint_balls = named<metaballs::JointBall, mb_array("joint_balls")>(v);
  m.jv_vertex = named<uint32_t, mb_array("jv_vertex")>(v);
  m.jv_ball = named<uint16_t, mb_array("jv_ball")>(v);
  m.jv_alpha = named<fx::Unit, mb_array("jv_alpha")>(v);
  m.jv_blend = named<fx::Unit, mb_array("jv_blend")>(v);
  m.jv_disp = named<fx::Vec3, mb_array("jv_disp")>(v);
  m.jv_laplacian = named<fx::Vec3, mb_array("jv_laplacian")>(v);
  m.jv_neighbour_begin = named<uint32_t, mb_array("jv_neighbour_begin")>(v);
  m.jv_neighbours = named<uint32_t, mb_array("jv_neighbours")>(v);
  m.jv_inv_count = named<fx::Unit, mb_array("jv_inv_count")>(v);
  m.overlaps = named<metaballs::OverlapRecord, mb_array("overlaps")>(v);
  m.overlap_vertices = named<uint32_t, mb_array("overlap_vertices")>(v);
  m.overlap_balls = named<uint16_t, mb_array("overlap_balls")>(v);
  if (v.header.layer_version >= metaballs::kMetaballsSectionVersion2) {  // action lines
    m.action_lines = named<metaballs::ActionLine, mb_array("action_lines")>(v);
    m.action_balls = named<metaballs::ActionBall, mb_array("action_balls")>(v);
  }
  // Before version 3 no writer paired jiggle balls under physical jiggle; a
  // section that does would have its per-step stiffness read as a coupling.
  if (v.header.layer_version < metaballs::kMetaballsSectionVersion3 && m.jiggle_rate_hz != 0 && !m.pairs.empty())
    return section_layer_fail(LoadError::kBadValue, v,
                              "pairs: stretch pairs with physical jiggle need layer version 3");
  const metaballs::LayerStatus st = metaballs::metaballs_validate(m, rig);
  if (!st.ok()) return section_layer_fail(LoadError::kBadValue, v, st.message);
  return {};
}

}  // namespace

LoadStatus metaballs_load(std::span<const SectionView> sections, const rig::Rig& rig, LayerSet* set) {
  for (const SectionView& v : sections) {
    if (v.id != metaballs::kSectionMetaballs) continue;
    set->metaballs.present = true;
    LoadStatus st = load_section(v, rig, &set->metaballs.model);
    if (!st.ok()) return st;
  }
  return {};
}

}  // namespace sinew::pipeline::stages
