// The overlays the page draws (skeleton, SPH particles, metaballs, muscles)
// against the skin of the same frame. A "daemon" pipeline at the stream's
// tick rate (sinewd converts the SPH gains to its rate_hz) produces the
// frames; the viewer's shadow pipeline is stepped with each frame as the
// feeds step it, and the frame message the page receives is decoded. Every
// bound comes from the rig at rest (radii of its limbs and of the SPH
// capsule, its ball radii), not from a run: an overlay in another pose,
// frame or unit than the skin leaves it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "host_tools/view/frame_message.hpp"

namespace {

using sinew::hal::output::DecodedPose;
using sinew::view::ViewRig;
namespace pipeline = sinew::pipeline;

struct OverlayPoint {
  double x = 0, y = 0, z = 0;
};

double overlay_distance(const OverlayPoint& a, const OverlayPoint& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

// Distance from p to the segment [a, b].
double overlay_segment_distance(const OverlayPoint& p, const OverlayPoint& a, const OverlayPoint& b) {
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double len2 = ux * ux + uy * uy + uz * uz;
  double s = len2 > 0 ? ((p.x - a.x) * ux + (p.y - a.y) * uy + (p.z - a.z) * uz) / len2 : 0;
  s = std::clamp(s, 0.0, 1.0);
  return overlay_distance(p, {a.x + s * ux, a.y + s * uy, a.z + s * uz});
}

double overlay_metres(int32_t q12_20, int32_t e) { return std::ldexp(static_cast<double>(q12_20), e - 20); }

// The frame message's float arrays by name, as the page's decode() reads them.
std::map<std::string, std::vector<double>> overlay_decode(const std::vector<uint8_t>& m) {
  uint32_t n = 0;
  for (int b = 0; b < 4; ++b) n |= uint32_t{m[static_cast<size_t>(b)]} << (8 * b);
  const std::string json(reinterpret_cast<const char*>(m.data()) + 4, n);
  std::map<std::string, std::vector<double>> out;
  size_t at = (4 + n + 3) / 4 * 4;
  size_t pos = json.find("\"arrays\":[");
  EXPECT_NE(pos, std::string::npos);
  while ((pos = json.find("[\"", pos + 1)) != std::string::npos) {
    const size_t name_end = json.find('"', pos + 2);
    const std::string name = json.substr(pos + 2, name_end - pos - 2);
    const size_t count = std::stoul(json.substr(name_end + 2));
    std::vector<double>& v = out[name];
    for (size_t k = 0; k < count; ++k, at += 4) {
      float f;
      std::memcpy(&f, m.data() + at, 4);
      v.push_back(static_cast<double>(f));
    }
  }
  EXPECT_EQ(at, m.size());
  return out;
}

std::vector<OverlayPoint> overlay_points(const std::vector<double>& xyz, size_t stride = 3) {
  std::vector<OverlayPoint> p;
  for (size_t k = 0; k + 2 < xyz.size(); k += stride) p.push_back({xyz[k], xyz[k + 1], xyz[k + 2]});
  return p;
}

// What the test derives from the rig at rest.
struct RigBounds {
  std::vector<int> dominant;        // per vertex: the joint of its largest influence
  std::vector<double> limb_radius;  // per joint: the largest rest distance of its vertices from its bone, m
  std::vector<int> first_child;     // per joint, -1 for a leaf
  std::vector<double> sph_reach;    // per SPH joint: capsule extent from the distal joint + 2 h, m
  double largest_ball_gap = 0;      // rest: the largest distance of a ball's centre from the skin minus its radius
  double edge = 0;                  // the longest rest triangle edge, m
};

std::vector<OverlayPoint> overlay_joint_origins(const pipeline::Pipeline& p) {
  std::vector<OverlayPoint> j;
  const int32_t e = p.rig->length_exponent;
  for (uint32_t k = 0; k < p.rig->joint_count(); ++k)
    j.push_back({overlay_metres(p.engine.model[k].t[0], e), overlay_metres(p.engine.model[k].t[1], e),
                 overlay_metres(p.engine.model[k].t[2], e)});
  return j;
}

std::vector<OverlayPoint> overlay_skin(const pipeline::Pipeline& p) {
  std::vector<OverlayPoint> s;
  const int32_t e = p.rig->length_exponent;
  const auto& v = p.engine.vertices.position;
  for (size_t k = 0; k < v[0].size(); ++k)
    s.push_back({overlay_metres(v[0][k], e), overlay_metres(v[1][k], e), overlay_metres(v[2][k], e)});
  return s;
}

double overlay_nearest(const OverlayPoint& p, const std::vector<OverlayPoint>& skin) {
  double best = 1e30;
  for (const OverlayPoint& s : skin) best = std::min(best, overlay_distance(p, s));
  return best;
}

RigBounds overlay_rig_bounds(const pipeline::Pipeline& rest) {
  const sinew::rig::Rig& r = *rest.rig;
  const int32_t e = r.length_exponent;
  RigBounds b;
  const std::vector<OverlayPoint> origin = overlay_joint_origins(rest);
  const std::vector<OverlayPoint> skin = overlay_skin(rest);
  b.first_child.assign(r.joint_count(), -1);
  for (uint32_t k = r.joint_count(); k-- > 0;)
    if (r.joints[k].parent >= 0) b.first_child[static_cast<size_t>(r.joints[k].parent)] = static_cast<int>(k);
  const uint32_t kk = r.influences_per_vertex;
  b.dominant.resize(r.vertex_count());
  b.limb_radius.assign(r.joint_count(), 0);
  for (uint32_t v = 0; v < r.vertex_count(); ++v) {
    uint32_t best = 0;
    for (uint32_t i = 1; i < kk; ++i)
      if (r.influence_weight[v * kk + i] > r.influence_weight[v * kk + best]) best = i;
    const int j = static_cast<int>(r.palette[r.influence_palette[v * kk + best]].joint);
    b.dominant[v] = j;
    const int c = b.first_child[static_cast<size_t>(j)];
    if (c >= 0) {
      const double d =
          overlay_segment_distance(skin[v], origin[static_cast<size_t>(j)], origin[static_cast<size_t>(c)]);
      b.limb_radius[static_cast<size_t>(j)] = std::max(b.limb_radius[static_cast<size_t>(j)], d);
    }
  }
  for (uint32_t s = 0; s < rest.sph.count; ++s) {
    const auto& m = rest.sph.model[s];
    const OverlayPoint joint = origin[m.joint.distal_joint];
    double extent = 0;
    for (uint32_t k = 0; k < m.particle_count(); ++k)
      extent = std::max(extent,
                        overlay_distance({overlay_metres(m.rest_model[0][k], e), overlay_metres(m.rest_model[1][k], e),
                                          overlay_metres(m.rest_model[2][k], e)},
                                         joint));
    b.sph_reach.push_back(extent + 2 * overlay_metres(m.params.h, e));
  }
  if (rest.metaballs.on)
    for (size_t k = 0; k < rest.metaballs.state.ball_center.size(); ++k) {
      const auto& c = rest.metaballs.state.ball_center[k];
      const double gap =
          overlay_nearest({overlay_metres(c.x, e), overlay_metres(c.y, e), overlay_metres(c.z, e)}, skin) -
          overlay_metres(rest.metaballs.state.model->ball_radius[k], e);
      b.largest_ball_gap = std::max(b.largest_ball_gap, gap);
    }
  for (size_t t = 0; t < r.triangles.size(); t += 3)
    for (int a = 0; a < 3; ++a)
      b.edge = std::max(b.edge, overlay_distance(skin[r.triangles[t + static_cast<size_t>(a)]],
                                                 skin[r.triangles[t + static_cast<size_t>((a + 1) % 3)]]));
  return b;
}

class OverlayRun {
 public:
  bool init(const ViewRig& rig, const pipeline::PipelineOptions& options) {
    arena_.assign(pipeline::pipeline_state_bytes(rig.loaded.rig, rig.loaded.layers, options) / 8 + 1, 0);
    return pipeline::pipeline_init(rig.loaded.rig, rig.loaded.layers, options, arena_.data(), arena_.size() * 8, &p_)
        .ok();
  }
  pipeline::Pipeline p_;

 private:
  std::vector<uint64_t> arena_;
};

// Each DOF at fraction f of its range (beyond [0, 1]: past its limit, clamped).
std::vector<int32_t> overlay_pose_inputs(const ViewRig& rig, double f) {
  std::vector<int32_t> in(rig.loaded.input_count(), 0);
  for (const auto& j : rig.loaded.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) {
      const double lo = j.dof_min[d], hi = j.dof_max[d];
      in[j.first_input + d] = static_cast<int32_t>(std::clamp(lo + f * (hi - lo), -2147483647.0, 2147483647.0));
    }
  return in;
}

// Runs the rig through poses at tick_hz (each reached over 1 s, then held
// 0.2 s) and checks every overlay of every 10th frame against its skin.
// metaballs: whether that layer runs (in both).
void check_overlays_follow_the_skin(const char* rig_name, uint32_t tick_hz, bool metaballs) {
  ViewRig rig;
  std::string error;
  ASSERT_TRUE(sinew::view::load_view_rig(rig_name, &rig, &error)) << error;
  pipeline::PipelineOptions daemon_options;
  daemon_options.tick_hz = tick_hz;  // as sinewd sets it from [loop] rate_hz
  // The anatomy layer is off in both: its elastic skin lags the bones by
  // centimetres within a tick of a shoulder move (a sim_core matter, not the
  // viewer's), so the daemon's skin would be off its own skeleton.
  daemon_options.stages.set(pipeline::Stage::kAnatomy, false);
  daemon_options.stages.set(pipeline::Stage::kMetaballs, metaballs);
  OverlayRun daemon;
  ASSERT_TRUE(daemon.init(rig, daemon_options));
  const RigBounds bounds = overlay_rig_bounds(daemon.p_);
  sinew::view::ShadowPipeline shadow;
  pipeline::PipelineOptions view_options;  // as sinew-view --layers sph,metaballs,barnet, no --tick-hz
  view_options.stages.set(pipeline::Stage::kAnatomy, false);
  view_options.stages.set(pipeline::Stage::kMetaballs, metaballs);
  ASSERT_TRUE(shadow.init(rig, view_options, &error)) << error;

  const int32_t e = rig.loaded.rig.length_exponent;
  const uint64_t period_ns = 1000000000ull / tick_hz;
  const uint32_t move = tick_hz, hold = tick_hz / 5;
  std::vector<int32_t> from = overlay_pose_inputs(rig, 0.5);
  std::fill(from.begin(), from.end(), 0);
  uint64_t tick = 0;
  double worst_sph = 0, worst_bone = 0, worst_ball = 0, worst_muscle = 0;
  double stretch_frame = 0, stretch_plain = 0;  // largest edge length / rest length (reported, not a bound)
  const auto& tri = rig.loaded.rig.triangles;
  const auto& rest_xyz = rig.loaded.rig.position;
  const auto edge_stretch = [&](const auto& xyz) {
    double worst = 0;
    for (size_t t = 0; t < tri.size(); t += 3)
      for (size_t a = 0; a < 3; ++a) {
        const uint32_t i = tri[t + a], k = tri[t + (a + 1) % 3];
        double d2 = 0, r2 = 0;
        for (size_t c = 0; c < 3; ++c) {
          const double d = static_cast<double>(xyz[c][i]) - xyz[c][k];
          const double r = static_cast<double>(rest_xyz[c][i]) - rest_xyz[c][k];
          d2 += d * d, r2 += r * r;
        }
        if (r2 > 0) worst = std::max(worst, std::sqrt(d2 / r2));
      }
    return worst;
  };
  for (const double f : {1.0, 0.0, 1.3, -0.3, 0.6}) {
    const std::vector<int32_t> to = overlay_pose_inputs(rig, f);
    for (uint32_t t = 1; t <= move + hold; ++t, ++tick) {
      const double s = std::min(1.0, static_cast<double>(t) / move);
      std::vector<int32_t> in(to.size());
      for (size_t i = 0; i < in.size(); ++i)
        in[i] = static_cast<int32_t>(from[i] + s * (static_cast<double>(to[i]) - from[i]));
      ASSERT_TRUE(pipeline::pipeline_step(&daemon.p_, in).ok());
      DecodedPose pose;
      pose.tick = tick;
      pose.timestamp_ns = tick * period_ns;
      pose.length_exponent = e;
      pose.vertex_count = rig.loaded.rig.vertex_count();
      pose.input_count = rig.loaded.input_count();
      for (int c = 0; c < 3; ++c)
        pose.position[c].assign(daemon.p_.engine.vertices.position[c].begin(),
                                daemon.p_.engine.vertices.position[c].end());
      pose.input_value = in;
      pose.input_status.assign(in.size(), 0);
      shadow.step_frame(pose);
      if (t % 10 != 0) continue;
      stretch_frame = std::max(stretch_frame, edge_stretch(pose.position));
      const std::vector<int32_t>* plain[3] = {&shadow.plain_skin(0), &shadow.plain_skin(1), &shadow.plain_skin(2)};
      stretch_plain =
          std::max(stretch_plain, edge_stretch(std::array<std::vector<int32_t>, 3>{*plain[0], *plain[1], *plain[2]}));
      const auto arrays = overlay_decode(sinew::view::frame_message(rig, pose, &shadow, {}, period_ns, {}, {}, ""));
      const std::vector<OverlayPoint> skin = overlay_points(arrays.at("position"));
      const std::vector<OverlayPoint> joints = overlay_points(arrays.at("joints"));
      const std::vector<OverlayPoint> truth = overlay_joint_origins(daemon.p_);
      const std::string where = std::string(rig_name) + " pose " + std::to_string(f) + " tick " + std::to_string(tick);

      // Skeleton: every bone's middle lies inside its limb: the median
      // distance of the bone's skin from the drawn segment within the limb's
      // rest radius, and the midpoint within that radius of its skin.
      for (uint32_t j = 0; j < joints.size(); ++j) {
        const int c = bounds.first_child[j];
        if (c < 0 || bounds.limb_radius[j] <= 0) continue;
        std::vector<double> d;
        const OverlayPoint mid{(joints[j].x + joints[static_cast<size_t>(c)].x) / 2,
                               (joints[j].y + joints[static_cast<size_t>(c)].y) / 2,
                               (joints[j].z + joints[static_cast<size_t>(c)].z) / 2};
        double nearest = 1e30;
        for (size_t v = 0; v < skin.size(); ++v)
          if (bounds.dominant[v] == static_cast<int>(j)) {
            d.push_back(overlay_segment_distance(skin[v], joints[j], joints[static_cast<size_t>(c)]));
            nearest = std::min(nearest, overlay_distance(skin[v], mid));
          }
        if (d.size() < 8) continue;
        std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
        const double median = d[d.size() / 2];
        // One edge of margin: the mesh's resolution (a ring's vertices
        // round a limb of that radius only at its vertices).
        const double limb = bounds.limb_radius[j] + bounds.edge;
        worst_bone = std::max(worst_bone, std::max(median, nearest) / limb);
        EXPECT_LE(median, limb) << where << ": bone " << j << " off its skin";
        EXPECT_LE(nearest, limb) << where << ": bone " << j << "'s middle off its skin";
      }
      // SPH: every particle within its capsule's reach of the distal joint in
      // the frame's pose: the rest extent (docs/sph.md: the capsule around
      // the distal joint), one kernel radius h of compression, one h of lag
      // behind a fast move, one edge. And the particles are the daemon's
      // own: the same rate and inputs give the same state (float rounding).
      const std::vector<OverlayPoint> particles = overlay_points(arrays.at("sph_position"));
      const auto& daemon_sph = daemon.p_.sph.joint;
      for (uint32_t js = 0, k = 0; js < daemon.p_.sph.count; ++js)
        for (size_t i = 0; i < daemon_sph[js].position[0].size(); ++i, ++k) {
          const OverlayPoint want{overlay_metres(daemon_sph[js].position[0][i], e),
                                  overlay_metres(daemon_sph[js].position[1][i], e),
                                  overlay_metres(daemon_sph[js].position[2][i], e)};
          ASSERT_LT(overlay_distance(particles.at(k), want), 1e-6)
              << where << ": particle " << k << " not the daemon's";
        }
      size_t first = 0;
      for (uint32_t js = 0; js < shadow.state().sph.count; ++js) {
        const auto& m = shadow.state().sph.model[js];
        const OverlayPoint joint = truth[m.joint.distal_joint];
        for (size_t k = first; k < first + m.particle_count(); ++k) {
          const double d = overlay_distance(particles[k], joint);
          const double reach = bounds.sph_reach[js] + bounds.edge;
          worst_sph = std::max(worst_sph, d / reach);
          EXPECT_LE(d, reach) << where << ": particle " << k << " away from joint " << m.joint.distal_joint;
          if (d > reach) break;
        }
        first += m.particle_count();
      }
      // Metaballs: a ball reaches the skin as at rest, give or take its
      // jiggle (its centre no farther from the skin than twice its radius
      // plus the rest pose's largest gap and one edge).
      const auto& balls = arrays.at("metaballs");
      for (size_t b = 0; b + 3 < balls.size(); b += 4) {
        const double gap = overlay_nearest({balls[b], balls[b + 1], balls[b + 2]}, skin) - 2 * balls[b + 3];
        const double bound = bounds.largest_ball_gap + bounds.edge;
        worst_ball = std::max(worst_ball, gap / bound);
        ASSERT_LE(gap, bound) << where << ": metaball " << b / 4 << " off the skin";
      }
      // Muscles: every surface point inside the skin, on the inner side of
      // its nearest skin vertex's normal (within one edge: the bend's crease).
      const auto& normal = daemon.p_.engine.vertices.normal;
      if (!normal[0].empty())
        for (const OverlayPoint& p : overlay_points(arrays.at("muscles"))) {
          size_t best = 0;
          double best_d = 1e30;
          for (size_t v = 0; v < skin.size(); ++v)
            if (const double d = overlay_distance(p, skin[v]); d < best_d) best_d = d, best = v;
          const double out = (p.x - skin[best].x) * std::ldexp(normal[0][best], -30) +
                             (p.y - skin[best].y) * std::ldexp(normal[1][best], -30) +
                             (p.z - skin[best].z) * std::ldexp(normal[2][best], -30);
          worst_muscle = std::max(worst_muscle, out / bounds.edge);
          ASSERT_LE(out, bounds.edge) << where << ": a muscle point outside the skin";
        }
    }
    from = to;
  }
  std::printf("%s at %u Hz: worst over the bound: bone %.3f, SPH %.3f, metaball %.3f, muscle %.3f\n", rig_name, tick_hz,
              worst_bone, worst_sph, worst_ball, worst_muscle);
  std::printf("%s: largest edge stretch over rest: frame %.3f, plain skinning %.3f\n", rig_name, stretch_frame,
              stretch_plain);
}

}  // namespace

TEST(ViewOverlayPlacement, ArmOverlaysFollowTheSkinAt100Hz) { check_overlays_follow_the_skin("arm", 100, true); }
// The hand's metaballs move its finger skin off the finger bones by more than
// a finger's radius (a sim_core matter): the hand runs SPH and bar-nets.
TEST(ViewOverlayPlacement, HandOverlaysFollowTheSkinAt100Hz) { check_overlays_follow_the_skin("hand", 100, false); }
