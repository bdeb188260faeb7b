// The non-default muscle shape of muscle_model.hpp (MuscleShape), step
// side: the §4.2 end-slice axes from bone normals, Table 1's per-slice
// translate / rotate edits and the "variable" pivot test. Pure functions on
// Q2.30 directions and Len points; muscle_step calls them.
#pragma once

#include <cstdint>
#include <span>

#include "muscle_model.hpp"
#include "muscle_state.hpp"
#include "sim_core/fixed/mat34.hpp"

namespace sinew::muscle {

// Whether a shape differs from the default one (a writer then needs MUSC v3).
bool is_default_shape(const MuscleShape& s);

// Table 1 "variable" pivot: true while the pivot lies strictly on the
// outer (-Y) side of the straight path from -> to, Y = Z x X with Z the
// path direction and X (x_raw made perpendicular to Z) the default X of the
// pivot slice. A degenerate path keeps the pivot on.
bool pivot_engaged(fx::Vec3 from, fx::Vec3 to, fx::Vec3 pivot, fx::Vec3 x_raw);

// §4.2 end-slice Z: the mean of the two attachment bones' outward normals
// (normal_local[k] turned by bones[k]'s linear part), negated for the
// insertion end (`inward`), minus its component along the end's X axis x,
// normalised; `fallback` when that vanishes (counted in *degenerate).
fx::Vec3 end_slice_z(const fx::Mat34& bone_a, fx::Vec3 normal_a, const fx::Mat34& bone_b, fx::Vec3 normal_b,
                     bool inward, fx::Vec3 x, fx::Vec3 fallback, uint32_t* degenerate);

// Table 1 edit of one slice frame: centre += translate along the default
// axes, then (unless the edit keeps the identity) the axes turn to
// edit.axis[] expressed in the default frame; Y is rebuilt as Z x X.
void apply_slice_edit(const SliceEdit& edit, SliceFrame* f, uint32_t* degenerate);

}  // namespace sinew::muscle
