#include "metaballs_section_writer.hpp"

#include <algorithm>
#include <cstring>

#include "host_tools/layers/sections/section_builder.hpp"

namespace sinew::layers {

LayerSection metaballs_section(const ::sinew::metaballs::MetaballModel& m) {
  const ::sinew::metaballs::MetaballsSectionParams p{m.joint_count,    m.vertex_count,     m.pbd_iterations,
                                                     m.jiggle_damping, m.smoothing_passes, m.smoothing_rate};
  // Version 1 without action lines (the bytes of rigs without them do not
  // change); version 2 appends them; version 3 when physical jiggle has
  // coupled pairs or overlap records of bones sharing no joint (the arrays of
  // version 2).
  const bool bone_pairs = std::any_of(m.overlaps.begin(), m.overlaps.end(),
                                      [](const metaballs::OverlapRecord& r) { return r.joint == metaballs::kNoJoint; });
  const bool v3 = (m.jiggle_rate_hz != 0 && !m.pairs.empty()) || bone_pairs;
  const bool v2 = v3 || !m.action_lines.empty();
  const uint32_t version = v3   ? ::sinew::metaballs::kMetaballsSectionVersion3
                           : v2 ? ::sinew::metaballs::kMetaballsSectionVersion2
                                : pipeline::kLayerSectionVersion;
  SectionBuilder b = section_builder(metaballs::kMetaballsSection, version, m.jiggle_rate_hz, p);
  b.array("inverse_bind", m.inverse_bind)
      .array("ball_rest", m.ball_rest)
      .array("ball_radius", m.ball_radius)
      .array("ball_bone", m.ball_bone)
      .array("ball_joint", m.ball_joint);
  b.array("ball_weight", m.ball_weight)
      .array("ball_jiggle", m.ball_jiggle)
      .array("pairs", m.pairs)
      .array("bulges", m.bulges);
  b.array("vertex_ball", m.vertex_ball).array("vertex_weight", m.vertex_weight).array("vertex_disp", m.vertex_disp);
  b.array("joint_balls", m.joint_balls)
      .array("jv_vertex", m.jv_vertex)
      .array("jv_ball", m.jv_ball)
      .array("jv_alpha", m.jv_alpha)
      .array("jv_blend", m.jv_blend);
  b.array("jv_disp", m.jv_disp)
      .array("jv_laplacian", m.jv_laplacian)
      .array("jv_neighbour_begin", m.jv_neighbour_begin)
      .array("jv_neighbours", m.jv_neighbours)
      .array("jv_inv_count", m.jv_inv_count);
  b.array("overlaps", m.overlaps).array("overlap_vertices", m.overlap_vertices).array("overlap_balls", m.overlap_balls);
  if (v2) b.array("action_lines", m.action_lines).array("action_balls", m.action_balls);
  return b.finish();
}

}  // namespace sinew::layers
