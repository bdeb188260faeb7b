// The default muscle shape of a rig spec's [[muscle]] (joint_anatomy)
// follows anatomically-based-modeling §4.2: end slices as wide as the
// origins and the insertions are apart, a fusiform profile between them
// (widest in the middle, wider than thick), and centres displaced outward
// by the extra thickness so the bone-side face runs straight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "host_tools/layers/anatomy/joint_anatomy.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::test {
namespace {

namespace ab = anatomy_build;

// A bone attachment's point in its joint frame (the builder's bone_point,
// in double): param scaled by the bone's box.
rigc::Vec3d default_shape_local(const ab::AnatomySpec& a, const ab::BoneAttachment& at) {
  const ab::BoneSize& b = a.bones[static_cast<size_t>(at.bone)];
  const rigc::Vec3d third{b.axis[1] * b.side[2] - b.axis[2] * b.side[1], b.axis[2] * b.side[0] - b.axis[0] * b.side[2],
                          b.axis[0] * b.side[1] - b.axis[1] * b.side[0]};
  rigc::Vec3d p{};
  for (size_t i = 0; i < 3; ++i)
    p[i] = at.param[0] * b.length * b.axis[i] + at.param[1] * b.radius * b.side[i] + at.param[2] * b.radius * third[i];
  return p;
}

double default_shape_distance(const rigc::Vec3d& a, const rigc::Vec3d& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// The built-in arm's biceps from a bare [[muscle]] (shoulder -> elbow).
ab::AnatomySpec default_shape_biceps(double thickness) {
  const rigc::RigSpec arm = rigc::builtin_arm();
  layers::RigGeometry g;
  std::string error;
  EXPECT_TRUE(layers::rig_geometry(arm, &g, &error)) << error;
  ab::MuscleRequest m;
  m.name = "biceps";
  m.origin = rigc::joint_index(arm, "shoulder");
  m.insertion = rigc::joint_index(arm, "elbow");
  m.thickness = thickness;
  ab::AnatomySpec a;
  std::vector<ab::MusclePath> paths;
  EXPECT_TRUE(ab::joint_anatomy(arm, g, {m}, ab::SkinRequest{}, &a, &paths, &error)) << error;
  return a;
}

TEST(MuscleDefaultShape, EndSlicesSpanTheAttachments) {
  // §4.2: "the width of the muscle (in X) is the distance between muscle
  // origin points, and muscle insertion points". The arm's frames are
  // rigid (no scale), so joint-frame distances are model distances.
  const ab::AnatomySpec a = default_shape_biceps(1.0);
  ASSERT_EQ(a.muscles.size(), 1u);
  const ab::MuscleSpec& s = a.muscles[0];
  const double origin_gap =
      default_shape_distance(default_shape_local(a, s.origin[0]), default_shape_local(a, s.origin[1]));
  const double insertion_gap =
      default_shape_distance(default_shape_local(a, s.insertion[0]), default_shape_local(a, s.insertion[1]));
  std::printf("default biceps: origins %.2f mm apart (slice 0 width %.2f mm), insertions %.2f mm (slice 7 %.2f mm)\n",
              origin_gap * 1e3, 2 * s.half_width[0] * 1e3, insertion_gap * 1e3, 2 * s.half_width[7] * 1e3);
  EXPECT_NEAR(2 * s.half_width[0], origin_gap, 1e-9);
  EXPECT_NEAR(2 * s.half_width[7], insertion_gap, 1e-9);
}

TEST(MuscleDefaultShape, FusiformWiderThanThickAndWidestInTheMiddle) {
  const ab::AnatomySpec a = default_shape_biceps(1.0);
  ASSERT_EQ(a.muscles.size(), 1u);
  const ab::MuscleSpec& s = a.muscles[0];
  std::printf("default biceps half-widths (mm):");
  for (double w : s.half_width) std::printf(" %.2f", w * 1e3);
  std::printf("\n");
  // "larger in the middle slices than in the end slices": rising to the
  // middle (slices 3 and 4) and falling after, strictly.
  for (size_t k = 0; k < 3; ++k) EXPECT_GT(s.half_width[k + 1], s.half_width[k]) << "slice " << k + 1;
  for (size_t k = 4; k < 7; ++k) EXPECT_GT(s.half_width[k], s.half_width[k + 1]) << "slice " << k;
  const double belly = std::max(s.half_width[3], s.half_width[4]);
  EXPECT_GT(belly, std::max(s.half_width[0], s.half_width[7]));
  // "larger across (in X) than in thickness (in Y)", every slice.
  for (size_t k = 0; k < 8; ++k) {
    EXPECT_GT(s.half_width[k], s.half_thickness[k]) << "slice " << k;
    EXPECT_GT(s.half_thickness[k], 0) << "slice " << k;
  }
  // `thickness` scales the belly, not the ends (§4.2 sets those from the
  // attachments): with 1.2 the end slices keep their width, every inner
  // slice widens, the middle ones the most. (The spindle profile itself is
  // the builder's choice where the paper gives no formula: joint_anatomy.hpp.)
  const ab::AnatomySpec thicker = default_shape_biceps(1.2);
  ASSERT_EQ(thicker.muscles.size(), 1u);
  const ab::MuscleSpec& thick = thicker.muscles[0];
  EXPECT_EQ(thick.half_width[0], s.half_width[0]);
  EXPECT_EQ(thick.half_width[7], s.half_width[7]);
  double widest_gain = 0;
  for (size_t k = 1; k < 7; ++k) {
    EXPECT_GT(thick.half_width[k], s.half_width[k]) << "slice " << k;
    widest_gain = std::max(widest_gain, thick.half_width[k] - s.half_width[k]);
  }
  EXPECT_EQ(widest_gain, std::max(thick.half_width[3] - s.half_width[3], thick.half_width[4] - s.half_width[4]));
}

TEST(MuscleDefaultShape, BulgeKeepsTheBoneSideFaceStraight) {
  // "the origins of the intermediate frames are slightly displaced in the
  // negative Y direction (outward from the underlying bone), to compensate
  // for the greater thickness of the muscle near its center": the bone-side
  // extreme (+Y) of each slice, half_thickness - bulge off the path, lies on
  // the straight line between the end slices' ones; ends are not displaced.
  const ab::AnatomySpec a = default_shape_biceps(1.0);
  ASSERT_EQ(a.muscles.size(), 1u);
  const ab::MuscleSpec& s = a.muscles[0];
  EXPECT_EQ(s.bulge[0], 0);
  EXPECT_EQ(s.bulge[7], 0);
  for (size_t k = 1; k < 7; ++k) {
    const double t = static_cast<double>(k) / 7.0;
    const double line = s.half_thickness[0] + (s.half_thickness[7] - s.half_thickness[0]) * t;
    EXPECT_GT(s.bulge[k], 0) << "slice " << k;
    EXPECT_NEAR(s.half_thickness[k] - s.bulge[k], line, 1e-12) << "slice " << k;
  }
}

}  // namespace
}  // namespace sinew::test
