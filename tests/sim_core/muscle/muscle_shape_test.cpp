// The non-default muscle shapes of anatomically-based-modeling §4.2-4.3 on
// the built-in arm, each against an oracle written from the paper in
// double precision (not from the builder's code):
//   - §4.2 end frames: X the line between the two origins (insertions), Z
//     the mean outward (inward) bone-surface normal there made
//     perpendicular to X, Y = Z x X;
//   - Table 1 translate / rotate of a slice frame from its default;
//   - Table 1 pivot "variable": the path runs through the pivot only while
//     the pivot lies outward (-Y) of the straight path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "anatomy_fixture.hpp"
#include "sim_core/muscle/muscle_validate.hpp"

namespace sinew::test {
namespace {

namespace ab = anatomy_build;
using ShapeV3 = std::array<double, 3>;

ShapeV3 shape_add(const ShapeV3& a, const ShapeV3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
ShapeV3 shape_sub(const ShapeV3& a, const ShapeV3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
ShapeV3 shape_scale(const ShapeV3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double shape_dot(const ShapeV3& a, const ShapeV3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
ShapeV3 shape_cross(const ShapeV3& a, const ShapeV3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
ShapeV3 shape_unit(const ShapeV3& a) { return shape_scale(a, 1 / std::sqrt(shape_dot(a, a))); }
double shape_gap(const ShapeV3& a, const ShapeV3& b) { return std::sqrt(shape_dot(shape_sub(a, b), shape_sub(a, b))); }
ShapeV3 shape_dir(fx::Vec3 v) {
  return {std::ldexp(static_cast<double>(v.x), -30), std::ldexp(static_cast<double>(v.y), -30),
          std::ldexp(static_cast<double>(v.z), -30)};
}
ShapeV3 shape_point(const ArmAnatomy& arm, fx::Vec3 v) { return {arm.metres(v.x), arm.metres(v.y), arm.metres(v.z)}; }

// Joint j's present transform applied to a joint-frame vector (and point).
ShapeV3 shape_turn(ArmAnatomy& arm, int j, const ShapeV3& v) {
  const fx::Mat34& m = arm.engine().model[static_cast<size_t>(j)];
  ShapeV3 r{};
  for (size_t i = 0; i < 3; ++i)
    for (size_t c = 0; c < 3; ++c) r[i] += std::ldexp(static_cast<double>(m.m[i][c]), -24) * v[c];
  return r;
}
ShapeV3 shape_place(ArmAnatomy& arm, int j, const ShapeV3& p) {
  const fx::Mat34& m = arm.engine().model[static_cast<size_t>(j)];
  return shape_add(shape_turn(arm, j, p), {arm.metres(m.t[0]), arm.metres(m.t[1]), arm.metres(m.t[2])});
}

// §4.1: an attachment's point in its joint frame, from the bone's box.
ShapeV3 shape_local(const ab::AnatomySpec& a, const ab::BoneAttachment& at) {
  const ab::BoneSize& b = a.bones[static_cast<size_t>(at.bone)];
  const ShapeV3 axis{b.axis[0], b.axis[1], b.axis[2]}, side{b.side[0], b.side[1], b.side[2]};
  return shape_add(shape_add(shape_scale(axis, at.param[0] * b.length), shape_scale(side, at.param[1] * b.radius)),
                   shape_scale(shape_cross(axis, side), at.param[2] * b.radius));
}

// The outward normal of the bone's surface at the attachment: the bone is a
// capsule about its axis segment [0, length], so the normal points from the
// segment's nearest point to the attachment.
ShapeV3 shape_bone_normal(const ab::AnatomySpec& a, const ab::BoneAttachment& at) {
  const ab::BoneSize& b = a.bones[static_cast<size_t>(at.bone)];
  const ShapeV3 axis{b.axis[0], b.axis[1], b.axis[2]};
  const ShapeV3 p = shape_local(a, at);
  const double t = std::fmin(std::fmax(shape_dot(p, axis), 0.0), b.length);
  return shape_unit(shape_sub(p, shape_scale(axis, t)));
}

struct ShapeEndFrame {
  ShapeV3 x, y, z;
};

// §4.2, as the paper states it, at the present pose.
ShapeEndFrame shape_paper_end_frame(ArmAnatomy& arm, const ab::AnatomySpec& a, const ab::BoneAttachment at[2],
                                    bool insertion) {
  const ShapeV3 p0 = shape_place(arm, at[0].bone, shape_local(a, at[0]));
  const ShapeV3 p1 = shape_place(arm, at[1].bone, shape_local(a, at[1]));
  const ShapeV3 x = shape_unit(shape_sub(p1, p0));
  ShapeV3 n = shape_add(shape_turn(arm, at[0].bone, shape_bone_normal(a, at[0])),
                        shape_turn(arm, at[1].bone, shape_bone_normal(a, at[1])));
  if (insertion) n = shape_scale(n, -1);  // "points into the insertion bone"
  const ShapeV3 z = shape_unit(shape_sub(n, shape_scale(x, shape_dot(n, x))));
  return {x, shape_cross(z, x), z};
}

TEST(MuscleShape, EndSliceAxesAreTheMeanBoneNormalsOfSection42) {
  ArmAnatomy arm([](ab::AnatomySpec& a) {
    for (ab::MuscleSpec& m : a.muscles) m.end_axes_from_bones = true;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  ArmAnatomy plain;
  ASSERT_TRUE(plain.ok()) << plain.error();
  const ab::AnatomySpec spec = ab::arm_anatomy(arm.spec());
  double worst = 0, least_change = 2;
  for (double angle : {0.0, 45.0, 100.0, 140.0}) {
    arm.set("elbow.0", angle);
    plain.set("elbow.0", angle);
    ASSERT_TRUE(arm.step_muscles().ok());
    ASSERT_TRUE(plain.step_muscles().ok());
    for (uint32_t m = 0; m < 2; ++m)
      for (bool insertion : {false, true}) {
        const ab::MuscleSpec& s = spec.muscles[m];
        const ShapeEndFrame want = shape_paper_end_frame(arm, spec, insertion ? s.insertion : s.origin, insertion);
        const uint32_t k = insertion ? muscle::kSlices - 1 : 0;
        const muscle::SliceFrame& f = arm.muscles().frames[m * muscle::kSlices + k];
        worst = std::fmax(worst, shape_gap(shape_dir(f.x), want.x));
        worst = std::fmax(worst, shape_gap(shape_dir(f.y), want.y));
        worst = std::fmax(worst, shape_gap(shape_dir(f.z), want.z));
        // The path-direction default is another frame: the test can tell.
        const muscle::SliceFrame& d = plain.muscles().frames[m * muscle::kSlices + k];
        least_change = std::fmin(least_change, shape_gap(shape_dir(d.z), want.z));
      }
  }
  std::printf("end frames vs §4.2 oracle: worst axis error %.3g; the path-direction Z differs by >= %.3f\n", worst,
              least_change);
  EXPECT_LT(worst, 1e-7);  // Q2.30 directions: ~100 LSB of 2^-30 (normalisations, rounded products)
  EXPECT_GT(least_change, 0.1);
}

TEST(MuscleShape, SliceTranslateMovesTheCentreInTheDefaultFrame) {
  const ShapeV3 t{0.002, -0.003, 0.004};  // metres, along the default X, Y, Z
  ArmAnatomy edited([&](ab::AnatomySpec& a) { a.muscles[0].slice_edit[3].translate = {t[0], t[1], t[2]}; });
  ArmAnatomy plain;
  ASSERT_TRUE(edited.ok()) << edited.error();
  ASSERT_TRUE(plain.ok()) << plain.error();
  double worst = 0;
  for (double angle : {0.0, 70.0, 130.0}) {
    edited.set("elbow.0", angle);
    plain.set("elbow.0", angle);
    ASSERT_TRUE(edited.step_muscles().ok());
    ASSERT_TRUE(plain.step_muscles().ok());
    for (uint32_t k = 0; k < muscle::kSlices; ++k) {
      const muscle::SliceFrame& d = plain.muscles().frames[k];
      const muscle::SliceFrame& e = edited.muscles().frames[k];
      ShapeV3 want = shape_point(plain, d.centre);
      if (k == 3)
        want =
            shape_add(want, shape_add(shape_add(shape_scale(shape_dir(d.x), t[0]), shape_scale(shape_dir(d.y), t[1])),
                                      shape_scale(shape_dir(d.z), t[2])));
      worst = std::fmax(worst, shape_gap(shape_point(edited, e.centre), want));
      EXPECT_TRUE(e.x == d.x && e.y == d.y && e.z == d.z) << "a translate keeps the axes, slice " << k;
    }
  }
  std::printf("translated slice centre vs Table 1 oracle: worst %.3g m\n", worst);
  EXPECT_LT(worst, 1e-7);  // ~100 Len LSB: rounded products along three axes
}

// R = Rz Ry Rx (degrees): columns are the turned X, Y, Z.
void shape_rotation(const ShapeV3& deg, double r[3][3]) {
  const double k = 3.14159265358979323846 / 180;
  const double cx = std::cos(deg[0] * k), sx = std::sin(deg[0] * k), cy = std::cos(deg[1] * k),
               sy = std::sin(deg[1] * k), cz = std::cos(deg[2] * k), sz = std::sin(deg[2] * k);
  const double m[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                          {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                          {-sy, cy * sx, cy * cx}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = m[i][j];
}

TEST(MuscleShape, SliceRotateTurnsTheFrameAndItsRing) {
  const ShapeV3 inner{10, -20, 30}, end{25, 0, 0};  // end slices turn about X only (§4.3)
  ArmAnatomy edited([&](ab::AnatomySpec& a) {
    a.muscles[1].slice_edit[2].rotate = {inner[0], inner[1], inner[2]};
    a.muscles[1].slice_edit[0].rotate = {end[0], end[1], end[2]};
  });
  ArmAnatomy plain;
  ASSERT_TRUE(edited.ok()) << edited.error();
  ASSERT_TRUE(plain.ok()) << plain.error();
  double worst = 0, ring_worst = 0;
  for (double angle : {0.0, 90.0}) {
    edited.set("elbow.0", angle);
    plain.set("elbow.0", angle);
    ASSERT_TRUE(edited.step_muscles().ok());
    ASSERT_TRUE(plain.step_muscles().ok());
    for (uint32_t k : {0u, 2u}) {
      double r[3][3];
      shape_rotation(k == 0 ? end : inner, r);
      const muscle::SliceFrame& d = plain.muscles().frames[muscle::kSlices + k];
      const muscle::SliceFrame& e = edited.muscles().frames[muscle::kSlices + k];
      const ShapeV3 axes[3] = {shape_dir(d.x), shape_dir(d.y), shape_dir(d.z)};
      ShapeV3 want[3];
      for (int c = 0; c < 3; ++c)
        want[c] = shape_add(shape_add(shape_scale(axes[0], r[0][c]), shape_scale(axes[1], r[1][c])),
                            shape_scale(axes[2], r[2][c]));
      worst = std::fmax(worst, shape_gap(shape_dir(e.x), want[0]));
      worst = std::fmax(worst, shape_gap(shape_dir(e.y), want[1]));
      worst = std::fmax(worst, shape_gap(shape_dir(e.z), want[2]));
      // The ring lies on the turned ellipse: centre + rx cos X' + ry sin Y'.
      const uint32_t ring = edited.muscles().ring_vertices;
      for (uint32_t j = 0; j < ring; ++j) {
        const double a = 2 * 3.14159265358979323846 * j / ring;
        const ShapeV3 p = shape_add(
            shape_add(shape_point(edited, e.centre), shape_scale(want[0], edited.metres(e.radius_x) * std::cos(a))),
            shape_scale(want[1], edited.metres(e.radius_y) * std::sin(a)));
        const ShapeV3 got{edited.muscle_vertex(0, 1, k, j), edited.muscle_vertex(1, 1, k, j),
                          edited.muscle_vertex(2, 1, k, j)};
        ring_worst = std::fmax(ring_worst, shape_gap(got, p));
      }
    }
  }
  std::printf("rotated slice frames vs Table 1 oracle: worst axis error %.3g, ring vertex %.3g m\n", worst, ring_worst);
  EXPECT_LT(worst, 1e-7);  // the fixed-point sines (1 LSB) and three rounded products per axis
  EXPECT_LT(ring_worst, 1e-7);
}

TEST(MuscleShape, VariablePivotIsUsedOnlyWhileTheMuscleBendsRoundIt) {
  ArmAnatomy arm([](ab::AnatomySpec& a) {
    for (ab::MuscleSpec& m : a.muscles) m.pivot_variable = true;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  const ab::AnatomySpec spec = ab::arm_anatomy(arm.spec());
  int engaged = 0, free = 0;
  double worst = 0;
  for (int angle = 0; angle <= 150; angle += 10) {
    arm.set("elbow.0", angle);
    ASSERT_TRUE(arm.step_muscles().ok());
    for (uint32_t m = 0; m < 2; ++m) {
      const ab::MuscleSpec& s = spec.muscles[m];
      ShapeV3 pts[4];
      const ab::BoneAttachment* at[4] = {&s.origin[0], &s.origin[1], &s.insertion[0], &s.insertion[1]};
      for (int i = 0; i < 4; ++i) pts[i] = shape_place(arm, at[i]->bone, shape_local(spec, *at[i]));
      const ShapeV3 from = shape_scale(shape_add(pts[0], pts[1]), 0.5),
                    to = shape_scale(shape_add(pts[2], pts[3]), 0.5);
      const ShapeV3 pivot = shape_place(arm, s.pivot.bone, shape_local(spec, s.pivot));
      // The straight path's default frame at the pivot slice (§4.2: X
      // interpolated between the end X axes, Z along the path, Y = Z x X).
      const double w = static_cast<double>(s.pivot_slice) / 7;
      const ShapeV3 x_raw = shape_add(shape_scale(shape_unit(shape_sub(pts[1], pts[0])), 1 - w),
                                      shape_scale(shape_unit(shape_sub(pts[3], pts[2])), w));
      const ShapeV3 z = shape_unit(shape_sub(to, from));
      const ShapeV3 x = shape_unit(shape_sub(x_raw, shape_scale(z, shape_dot(x_raw, z))));
      const double outward = -shape_dot(shape_sub(pivot, from), shape_cross(z, x));  // along -Y
      if (std::fabs(outward) < 1e-5) continue;  // on the switch: either path is right
      const bool on = outward > 0;
      (on ? engaged : free) += 1;
      const double want = on ? shape_gap(pivot, from) + shape_gap(to, pivot) : shape_gap(to, from);
      worst = std::fmax(worst, std::fabs(arm.metres(arm.muscles().length[m]) - want));
    }
  }
  std::printf("variable pivots over 0..150 deg: %d poses through the pivot, %d straight; worst length error %.3g m\n",
              engaged, free, worst);
  EXPECT_GT(engaged, 0);
  EXPECT_GT(free, 0);  // a fixed pivot would be used at every pose and fail the lengths below
  EXPECT_LT(worst, 1e-7);
}

TEST(MuscleShape, BuilderRefusesEditsThePaperDoesNotAllow) {
  ArmAnatomy moved_end([](ab::AnatomySpec& a) { a.muscles[0].slice_edit[7].translate = {0.001, 0, 0}; });
  EXPECT_FALSE(moved_end.ok());
  EXPECT_NE(moved_end.error().find("end slices cannot be translated"), std::string::npos) << moved_end.error();
  ArmAnatomy no_pivot([](ab::AnatomySpec& a) {
    a.muscles[0].has_pivot = false;
    a.muscles[0].pivot_variable = true;
  });
  EXPECT_FALSE(no_pivot.ok());
  EXPECT_NE(no_pivot.error().find("needs a pivot"), std::string::npos) << no_pivot.error();
  ArmAnatomy far([](ab::AnatomySpec& a) { a.muscles[0].slice_edit[3].rotate = {0, 95, 0}; });
  EXPECT_FALSE(far.ok());
  EXPECT_NE(far.error().find("[-90, 90]"), std::string::npos) << far.error();
}

// The runtime validator (what a loaded MUSC v3 section goes through)
// refuses shapes the paper's edits cannot produce.
TEST(MuscleShape, ValidatorRefusesBadShapes) {
  ArmAnatomy arm([](ab::AnatomySpec& a) { a.muscles[0].end_axes_from_bones = true; });
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_EQ(arm.model().shapes.size(), 2u);
  const auto refused = [&](auto corrupt, const char* expected) {
    std::vector<muscle::MuscleShape> shapes = arm.model().shapes;
    std::vector<muscle::MuscleRecord> muscles = arm.model().muscles;
    corrupt(shapes, muscles);
    muscle::MuscleModel m = arm.muscle_model();
    m.shapes = shapes;
    m.muscles = muscles;
    const muscle::LayerStatus st = muscle::muscle_validate(m, arm.rig());
    EXPECT_FALSE(st.ok()) << expected;
    EXPECT_NE(std::string(st.message).find(expected), std::string::npos) << st.message;
  };
  using Shapes = std::vector<muscle::MuscleShape>;
  using Muscles = std::vector<muscle::MuscleRecord>;
  refused([](Shapes& s, Muscles&) { s.pop_back(); }, "one per muscle");
  refused([](Shapes& s, Muscles&) { s[0].slice[0].translate.x = 1; }, "end slices cannot be translated");
  refused(
      [](Shapes& s, Muscles&) {  // a quarter turn about Z
        s[1].slice[7].axis[0] = {0, fx::kUnitOne, 0};
        s[1].slice[7].axis[1] = {-fx::kUnitOne, 0, 0};
      },
      "end slices turn about X only");
  refused([](Shapes& s, Muscles&) { s[1].slice[3].axis[1] = {0, fx::kUnitOne / 2, 0}; }, "unit vectors");
  refused([](Shapes& s, Muscles&) { s[1].slice[3].axis[1] = {fx::kUnitOne, 0, 0}; }, "orthogonal");
  refused([](Shapes& s, Muscles&) { s[0].end_normal[2] = {0, 0, 0}; }, "bone normals must be unit vectors");
  refused([](Shapes& s, Muscles&) { s[0].end_axes = 2; }, "unknown end-axes mode");
  refused(
      [](Shapes& s, Muscles& m) {
        s[0].pivot_mode = static_cast<uint8_t>(muscle::PivotMode::kVariable);
        m[0].pivot_bone = -1;
      },
      "a variable pivot needs a pivot");
}

}  // namespace
}  // namespace sinew::test
