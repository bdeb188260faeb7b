// Builder options of the metaballs layer: how balls are placed and weighted,
// the PBD parameters, and the jiggle and bulge regions. docs/metaballs.md
// lists the TOML keys these are meant to be read from ([metaballs] table of a
// rig spec). Lengths are in model units (the rig spec's), fractions in [0, 1].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sinew::metaballs_build {

// Balls of `bone` whose position along the bone (0 at its joint, 1 at its
// end) lies in [from, to] jiggle on a spring of `stiffness` in (0, 1]
// (fraction of the gap to the kinematic centre closed per step; softer
// springs swing farther).
struct JiggleRegion {
  std::string bone;
  double from = 0, to = 1;
  double stiffness = 0.2;
};

// Balls of `bone` in [from, to] grow with the angle between bones
// `angle_a` and `angle_b`: r = r0 (1 + gain (1 - cos theta) / 2), gain in [0,
// 1).
struct BulgeRegion {
  std::string bone;
  double from = 0, to = 1;
  std::string angle_a, angle_b;
  double gain = 0.3;
};

// An action line (a simplified muscle or tendon): from the point `origin_at`
// along bone `origin` (0 its joint, 1 its end) to `insertion_at` along bone
// `insertion`, both shifted by `side` (model units, e.g. to the belly's side
// of the bones). The balls of either bone within `reach` (model units) of the
// segment at rest follow it, each keeping its rest distance from its point
// of the line with `stiffness` per PBD sweep.
struct ActionLineSpec {
  std::string origin, insertion;
  double origin_at = 0.3, insertion_at = 0.2;
  double side[3] = {0, 0, 0};
  double reach = 0.05;
  double stiffness = 0.5;
};

struct Options {
  // Placement: balls along each bone, `ball_spacing` apart; if
  // target_ball_count > 0 the spacing is chosen to give about that many.
  double ball_spacing = 0.01;
  int target_ball_count = 0;
  // w^gamma of a vertex's kVertexBalls nearest balls ~ (|v - c| /
  // r)^-weight_power.
  int weight_power = 16;
  // Stretch pairs: balls of rest distance < pair_reach * (r_a + r_b).
  double pair_reach = 0.6;
  double stretch_stiffness = 1.0;
  int pbd_iterations = 4;
  // Per-step jiggle (jiggle_frequency = 0 only): damping is the velocity
  // kept per step, in [0, 1), and each region's `stiffness` the spring's
  // per-step gain; the motion then depends on the tick rate.
  double jiggle_damping = 0.9;
  double jiggle_stretch_stiffness = 0.5;
  // Jiggle in physical units (metaballs::jiggle_gains), the default: every
  // jiggle ball swings at jiggle_frequency (Hz) and its swing falls to 5 %
  // within the time window jiggle_window (W_t, seconds) at any tick rate;
  // the per-step stiffness and damping are computed for rate_hz, and the
  // regions' `stiffness`, jiggle_damping and jiggle_stretch_stiffness are
  // not used (jiggle_coupling sets the springs instead). The paper names no values: 4 Hz within 0.4 s is an
  // underdamped swing (damping ratio sigma / omega0 = 0.29, 1.6 periods in
  // W_t) that a stop of u m/s starts at u / (2 pi f), 2 cm at 0.5 m/s. A
  // model without jiggle regions is the same either way.
  double jiggle_frequency = 4;
  double jiggle_window = 0.4;
  // With physical jiggle, the paper's springs (eq. (3)) between a jiggle ball
  // and its neighbouring balls are springs of this frequency (Hz) per unit
  // mass, solved as XPBD constraints so they too act alike at any rate
  // (metaballs::coupling_gains); 0 leaves the jiggle balls uncoupled. At
  // most rate_hz / (2 pi). The default is the swing's own frequency.
  double jiggle_coupling = 4;
  uint32_t rate_hz = 1000;
  std::vector<JiggleRegion> jiggle;
  std::vector<BulgeRegion> bulge;
  std::vector<ActionLineSpec> action_lines;  // none by default
  // Joint balls at every joint with a parent and a degree of freedom (or the
  // named ones). Region: full weight up to joint_inner, none beyond
  // joint_outer, both in multiples of the joint's surface radius (the
  // distance from the joint to the nearest vertex of its two bones).
  std::vector<std::string> joint_balls;
  double joint_inner = 1.0;
  double joint_outer = 1.6;
  int smoothing_passes = 0;
  double smoothing_rate = 0.5;
  // Overlap candidates: 0 (the default) derives them from the joint's DOF
  // range, complete over it (docs/metaballs.md, "Why the offline candidate
  // lists are complete"); > 0: the vertices and balls within that many
  // surface radii of the joint, which can miss overlaps at deep flexion.
  double overlap_reach = 0;
  // Overlap between bones that share no joint but can meet (fingers side by
  // side, a fingertip and the palm), candidates from the joints' ranges
  // (bone_pair_overlap.hpp); false: between the two bones of a joint only.
  bool overlap_between_bones = true;
};

// Empty if the options are usable, else a message naming the field.
std::string check_options(const Options& o);

}  // namespace sinew::metaballs_build
