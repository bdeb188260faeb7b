#include "step.hpp"

#include "kernels.hpp"
#include "sim_core/rig/message.hpp"

namespace sinew::metaballs {
namespace {

LayerStatus fail(LayerError e, const char* field, size_t got, size_t want) {
  LayerStatus s;
  s.error = e;
  rig::MessageBuilder(s.message, sizeof(s.message))
      .text(field)
      .text(": length ")
      .unsigned_number(got)
      .text(", the model needs ")
      .unsigned_number(want);
  return s;
}

}  // namespace

LayerStatus metaballs_step(MetaballState* state, std::span<const fx::Mat34> joint_model,
                           const skin::SkinnedVertices& out, const layer::Workers* workers) {
  if (state == nullptr || state->model == nullptr || state->bone.size() != state->model->joint_count) {
    LayerStatus s;
    s.error = LayerError::kNotReady;
    rig::MessageBuilder(s.message, sizeof(s.message)).text("state: not initialised (call metaballs::init)");
    return s;
  }
  const MetaballModel& m = *state->model;
  if (joint_model.size() != m.joint_count)
    return fail(LayerError::kBadSize, "joint_model", joint_model.size(), m.joint_count);
  static const char* const kAxis[3] = {"out.position[0]", "out.position[1]", "out.position[2]"};
  for (int a = 0; a < 3; ++a)
    if (out.position[a].size() != m.vertex_count)
      return fail(LayerError::kBadSize, kAxis[a], out.position[a].size(), m.vertex_count);

  detail::compute_bones(m, joint_model, state);
  detail::compute_balls(m, state);
  detail::solve_pbd(m, state);
  detail::deform_vertices(m, joint_model, state, out, detail::deform_kernel_default(), workers);
  detail::smooth_joint_region(m, state, out);
  state->stats.projected_vertices = state->features.overlap ? detail::resolve_overlaps(m, joint_model, *state, out) : 0;
  ++state->stats.steps;
  return {};
}

}  // namespace sinew::metaballs
