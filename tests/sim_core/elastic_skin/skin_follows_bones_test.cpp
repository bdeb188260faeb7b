// The elastic skin through the pipeline (every layer the built-in rigs
// carry, at the daemon's 100 Hz and at 1 kHz) over a motion with large fast
// shoulder moves and every joint driven past its limits: each skin vertex
// stays near the virtual anchor its bones (and muscles) carry, and no edge
// stretches beyond what its springs allow. A skin that trails the bones
// (warm-started where the bones were a tick ago) or rides on a muscle its
// bones do not move fails both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace {

namespace pl = sinew::pipeline;

double follow_units(int64_t len) { return static_cast<double>(len) / 1048576.0; }  // Q12.20 -> rig units

// Squared distances, and one square root per measured maximum (sqrt is
// monotonic, so the maximum's root is the roots' maximum): the checks run
// every tick over every edge, and under qemu's soft floating point they
// cost more than the pipeline step they check.
double follow_distance2(const std::span<sinew::fx::Len> (&a)[3], uint32_t i, const std::span<sinew::fx::Len> (&b)[3],
                        uint32_t j) {
  double d2 = 0;
  for (int c = 0; c < 3; ++c) {
    const double d = follow_units(int64_t{a[c][i]} - b[c][j]);
    d2 += d * d;
  }
  return d2;
}

// The inputs at time t: every DOF swings sinusoidally 5 % past both limits
// (as the simulated rig does, periods 2 + 0.37 i s); the first joint with
// DOFs (the shoulder, the wrist) instead jumps between its limits every
// 0.25 s: a large move within one tick.
void follow_inputs(const sinew::rig::Rig& rig, double t, std::vector<int32_t>* inputs) {
  bool first = true;
  for (const sinew::rig::JointRecord& j : rig.joints) {
    for (uint32_t d = 0; d < j.dof_count; ++d) {
      const double lo = j.dof_min[d], hi = j.dof_max[d];
      const double centre = (lo + hi) / 2, half = (hi - lo) / 2 * 1.05;
      const size_t i = j.first_input + d;
      double v = centre + half * std::sin(2 * M_PI * t / (2.0 + 0.37 * static_cast<double>(i)));
      if (first) v = (static_cast<int>(t / 0.25) % 2 == 0) ? centre - half : centre + half;
      (*inputs)[i] = static_cast<int32_t>(std::clamp(v, -2147483648.0, 2147483647.0));
    }
    if (j.dof_count > 0) first = false;
  }
}

// Largest edge length / rest length of a mesh over the skin's edges.
double follow_stretch(const sinew::elastic_skin::SkinModel& skin, const std::span<sinew::fx::Len> (&p)[3]) {
  double worst2 = 0;
  for (const sinew::elastic_skin::Edge& e : skin.edges) {
    const double rest = follow_units(e.rest);
    worst2 = std::max(worst2, follow_distance2(p, e.a, p, e.b) / (rest * rest));
  }
  return std::sqrt(worst2);
}

void follow_run(const std::string& name, uint32_t hz, double seconds) {
  std::string error;
  auto l = sinew::test::builtin_with_layers(name, &error);
  ASSERT_NE(l, nullptr) << error;
  pl::PipelineOptions options;
  options.tick_hz = hz;
  ASSERT_TRUE(l->start(options, &error)) << error;
  const sinew::elastic_skin::SkinModel& skin = l->layers.anatomy.skin;
  // The bound on |skin - anchor| (§5.1-5.6): the relaxed skin sits on its
  // virtual anchor, pushed out over the fat and the muscles beneath it.
  // Fat: the thickest. Muscles: a slice swells by sqrt(rest / present
  // length) (§4.4), at most 2x (the step's clamp): its thickness across
  // (2 half-thicknesses) plus its bulge offset at most double. Margin: one
  // mean rest edge, a single spring's pull from a neighbour.
  double fat = 0, muscle = 0, mean_edge = 0;
  for (uint32_t v = 0; v < skin.vertex_count; ++v) fat = std::max(fat, follow_units(skin.fat[v]));
  fat += follow_units(skin.solver.fat_thickness);
  for (const sinew::muscle::MuscleRecord& m : l->layers.anatomy.muscles.muscles)
    for (uint32_t k = 0; k < sinew::muscle::kSlices; ++k)
      muscle = std::max(muscle, 2 * follow_units(m.half_thickness[k]) + follow_units(m.bulge[k]));
  for (const sinew::elastic_skin::Edge& e : skin.edges) mean_edge += follow_units(e.rest);
  mean_edge /= static_cast<double>(std::max<size_t>(1, skin.edges.size()));
  const double bound = fat + muscle + mean_edge;

  std::vector<int32_t> inputs(l->pipeline.input_count, 0);
  const sinew::elastic_skin::SkinState& s = l->pipeline.anatomy.skin;
  double worst_offset2 = 0, worst_skin = 0, worst_anchors = 0, worst_plain = 0, worst_ratio = 0;
  double last_anchors[3] = {1, 1, 1};
  int worst_tick = -1;
  for (int k = 0; k < static_cast<int>(seconds * hz); ++k) {
    follow_inputs(*l->pipeline.rig, static_cast<double>(k) / hz, &inputs);
    const pl::PipelineStatus st = pl::pipeline_step(&l->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
    for (uint32_t v = 0; v < skin.vertex_count; ++v) {
      const double d2 = follow_distance2(s.position, v, s.anchor, v);
      if (d2 > worst_offset2) worst_offset2 = d2, worst_tick = k;
    }
    const double skin_stretch = follow_stretch(skin, s.position);
    const double anchor_stretch = follow_stretch(skin, s.anchor);
    worst_skin = std::max(worst_skin, skin_stretch);
    worst_anchors = std::max(worst_anchors, anchor_stretch);
    worst_plain = std::max(worst_plain, follow_stretch(skin, l->pipeline.reference));
    // The springs pull every edge towards its rest length, so a relaxed
    // skin is no more stretched than its anchor mesh (the bones carry it
    // as skinning carries the skin) but for the push-out over muscles and
    // fat, which lengthens a ring around a limb of radius r by (r + t) / r
    // <= 1.5 for t <= r / 2. The relaxation is warm-started: a few rounds
    // a tick leave part of the last ticks' shape (about 2/3 a tick at 4
    // rounds), so the anchors of the last 3 ticks count too.
    const double anchors = std::max({anchor_stretch, last_anchors[0], last_anchors[1], last_anchors[2]});
    worst_ratio = std::max(worst_ratio, skin_stretch / anchors);
    last_anchors[2] = last_anchors[1];
    last_anchors[1] = last_anchors[0];
    last_anchors[0] = anchor_stretch;
  }
  const double worst_offset = std::sqrt(worst_offset2);
  std::printf(
      "%s at %u Hz: |skin - anchor| up to %.3f rig units (bound %.3f, tick %d); edge stretch: skin %.2fx, "
      "anchors %.2fx, plain skinning %.2fx; skin / anchors %.2f (bound 1.5)\n",
      name.c_str(), hz, worst_offset, bound, worst_tick, worst_skin, worst_anchors, worst_plain, worst_ratio);
  EXPECT_LE(worst_offset, bound);
  EXPECT_LE(worst_ratio, 1.5);
}

TEST(SkinFollowsBones, ArmAt100Hz) { follow_run("arm", 100, 3.0); }
TEST(SkinFollowsBones, HandAt100Hz) { follow_run("hand", 100, 3.0); }
TEST(SkinFollowsBones, ArmAt1kHz) { follow_run("arm", 1000, 1.0); }
TEST(SkinFollowsBones, HandAt1kHz) { follow_run("hand", 1000, 1.0); }

}  // namespace
