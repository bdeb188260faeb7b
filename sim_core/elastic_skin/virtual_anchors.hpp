// Virtual anchors mapped forward (anatomically-based-modeling §5.1): each
// skin vertex's rest position relative to its component, placed for this
// step, with the component-carried skin normal.
//   bone anchors:   (1 - w) * B_a * local_a + w * B_b * local_b
//   muscle anchors: the parametric trilinear ("tri-affine") map of the cell
//                   between two slices, evaluated forward at (s, t, u).
#pragma once

#include <span>

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "skin_model.hpp"

namespace sinew::elastic_skin {

struct AnchorPoint {
  fx::Vec3 position{0, 0, 0};  // Len
  fx::Vec3 normal{0, 0, 0};    // Q2.30 unit (zero only if the stored normal is zero)
};

// The cell's corners: ring vertices at 0, 1/4, 1/2 and 3/4 of a turn of the
// two slices, in the order c00, c10, c11, c01 (Figure 6's eight vertices).
void muscle_cell(const muscle::MuscleState& m, uint32_t muscle, uint32_t segment, fx::Vec3 corners[8]);

// Tri-affine map: bilinear in (s, t) on each slice's quad, linear in u
// between the slices; parameters Q8.24. Products use 128-bit intermediates.
fx::Vec3 trilinear(const fx::Vec3 corners[8], const fx::Lin param[3]);

// Maps one validated anchor forward.
AnchorPoint map_anchor(const Anchor& a, std::span<const fx::Mat34> bones, const muscle::MuscleState& m);

}  // namespace sinew::elastic_skin
