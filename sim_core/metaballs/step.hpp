// The metaballs step job (metaballs-pbd-skinning), ozz style: spans in, spans
// out, validated sizes, no allocation, bounded work.
//
//   inputs:  joint_model — model-space transforms of the skeleton's joints
//            (engine::Engine::model after engine_step), one per model joint
//   outputs: out.position[3] — deformed vertex positions, Len, SoA, one per
//            model vertex (normals are not written)
//
// Stages, in order (each cites its equation):
//   1. bone deformations T_j = model_j * inverse_bind_j and their rotations;
//   2. normal balls: centres by eq. (2), rotations blended by nlerp, bulge
//      radii from the angle between bones;
//   3. PBD: jiggle balls integrate (Verlet, damped) and are pulled to their
//      kinematic centre by a spring; stretch constraints of eq. (3) are
//      projected a fixed number of sweeps;
//   4. vertices: eq. (4) from the normal balls, eq. (5) from the joint ball,
//      blended by eq. (1);
//   5. shape-preserving Laplacian smoothing of the joint-region vertices;
//   6. surface overlapping: projection onto the interior plane.
// Worst-case work: O(joints + iterations * pairs + vertices * kVertexBalls +
// passes * joint-region neighbours + overlap candidates), all bounded by the
// validated model.
#pragma once

#include <span>

#include "sim_core/layer/workers.hpp"
#include "sim_core/skin/skinning.hpp"
#include "state.hpp"

namespace sinew::metaballs {

// Returns an error (and changes nothing) if the state is not initialised or a
// span's size disagrees with the model. workers (optional): the per-vertex
// deformation (stage 4) runs over them; the words written are the same for
// any number of workers (sim_core/layer/workers.hpp).
LayerStatus metaballs_step(MetaballState* state, std::span<const fx::Mat34> joint_model,
                           const skin::SkinnedVertices& out, const layer::Workers* workers = nullptr);

}  // namespace sinew::metaballs
