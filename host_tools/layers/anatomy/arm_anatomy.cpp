#include "anatomy_spec.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::anatomy_build {

AnatomySpec arm_anatomy(const rigc::RigSpec& arm) {
  AnatomySpec a;
  const int shoulder = rigc::joint_index(arm, "shoulder");
  const int elbow = rigc::joint_index(arm, "elbow");
  // Bone boxes: upper arm 30 cm, forearm pieces 12 and 13 cm, hand 10 cm;
  // bone radius 1.2 cm.
  for (size_t j = 0; j < arm.joints.size(); ++j) a.bones.push_back({0.10, 0.012});
  a.bones[static_cast<size_t>(shoulder)].length = 0.30;
  a.bones[static_cast<size_t>(elbow)].length = 0.12;
  if (arm.joints.size() > 2) a.bones[2].length = 0.13;

  // Flexion turns the forearm towards +y: the biceps lies on +y, X along +z
  // so that -Y = Z x X points outward (+y).
  MuscleSpec biceps;
  biceps.name = "biceps";
  biceps.origin[0] = {shoulder, {0.1, 2.0, -0.8}};
  biceps.origin[1] = {shoulder, {0.1, 2.0, 0.8}};
  biceps.insertion[0] = {elbow, {0.35, 1.2, -0.6}};
  biceps.insertion[1] = {elbow, {0.35, 1.2, 0.6}};
  // The belly runs along the humerus to a pivot in front of its distal end,
  // then bends over the elbow: flexion shortens the path and thickens the
  // belly without lifting it off the bone.
  biceps.has_pivot = true;
  biceps.pivot = {shoulder, {0.85, 1.8, 0}};
  biceps.pivot_slice = 6;
  biceps.half_width = {0.008, 0.016, 0.020, 0.022, 0.022, 0.018, 0.012, 0.006};
  biceps.half_thickness = {0.004, 0.010, 0.014, 0.016, 0.016, 0.013, 0.008, 0.004};
  biceps.bulge = {0, 0.003, 0.005, 0.006, 0.006, 0.005, 0.003, 0};
  a.muscles.push_back(biceps);

  // Triceps on -y: X along -z so that -Y points to -y; it bends around a
  // pivot on the back of the humerus' distal end.
  MuscleSpec triceps;
  triceps.name = "triceps";
  triceps.origin[0] = {shoulder, {0.1, -2.0, 0.8}};
  triceps.origin[1] = {shoulder, {0.1, -2.0, -0.8}};
  triceps.insertion[0] = {elbow, {-0.1, -1.5, 0.5}};
  triceps.insertion[1] = {elbow, {-0.1, -1.5, -0.5}};
  triceps.has_pivot = true;
  triceps.pivot = {shoulder, {0.9, -2.25, 0}};
  triceps.pivot_slice = 6;
  triceps.half_width = {0.008, 0.016, 0.020, 0.022, 0.020, 0.018, 0.014, 0.008};
  triceps.half_thickness = {0.004, 0.009, 0.011, 0.012, 0.011, 0.010, 0.007, 0.004};
  triceps.bulge = {0, 0.002, 0.004, 0.004, 0.004, 0.003, 0.002, 0};
  a.muscles.push_back(triceps);

  PrimitiveSpec bp;  // biceps belly: a boxy superellipsoid (p = 4)
  bp.kind = 2;
  bp.attach = 1;
  bp.exponent = 4;
  bp.index = 0;
  bp.segment = 3;
  bp.extent = {0.016, 0.013, 0.09};
  a.primitives.push_back(bp);
  PrimitiveSpec tp;  // triceps belly: an ellipsoid (p = 2)
  tp.kind = 2;
  tp.attach = 1;
  tp.exponent = 2;
  tp.index = 1;
  tp.segment = 2;
  tp.extent = {0.016, 0.012, 0.07};
  a.primitives.push_back(tp);

  // Fasciae at the bellies: the outermost ring vertex (3/4 turn: -Y) of slice 4.
  a.skin.bands.push_back({-1, 0, 4, 6, 0.5, {}});
  a.skin.bands.push_back({-1, 1, 3, 6, 0.5, {}});
  return a;
}

}  // namespace sinew::anatomy_build
