#include "metaballs_compile.hpp"

#include <algorithm>

#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/layers/metaballs/metaballs_section_writer.hpp"

namespace sinew::layers {

bool HostLayer<pipeline::Stage::kMetaballs>::compile(const LayerCompile& c, const Tables& table, std::string* error) {
  if (!table.on) return true;
  const RigGeometry& g = c.geometry;
  metaballs_build::Options o = table.options;
  o.rate_hz = c.rate_hz;  // physical jiggle gains for the rig's tick rate
  double mean = 0, total = 0;
  int radii = 0;
  for (size_t j = 0; j < g.skin_radius.size(); ++j) {
    if (g.skin_radius[j] > 0) mean += g.skin_radius[j], ++radii;
    if (!g.vertices_of[j].empty()) total += g.bone_length[j];
  }
  if (radii == 0) return layer_fail(table.where, "no skin vertex is weighted to any joint", error);
  mean /= radii;
  o.ball_spacing = table.ball_spacing > 0 ? table.ball_spacing : std::max(0.22 * mean, total / 3000);
  metaballs_build::Build built;
  if (!metaballs_build::build(c.spec, o, &built, error)) return layer_fail(table.where, *error, error);
  c.sections->push_back(metaballs_section(built.model()));
  c.report->push_back("metaballs: " + std::to_string(built.ball_rest.size()) + " balls " +
                      report_number(o.ball_spacing) + " apart, " + std::to_string(built.joint_balls.size()) +
                      " joint balls, " + std::to_string(built.jv_vertex.size()) + " joint-region vertices");
  return true;
}

}  // namespace sinew::layers
