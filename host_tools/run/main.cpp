// sinew-run: the main job's computation on a built-in rig, as fast as it
// can: the built-in blob with its layers (the one the daemon embeds), run
// through sim_core's pipeline over the built-in joint sweep. Prints the rig
// summary, the step time per pipeline stage and the determinism hash of the
// outputs.
//   sinew-run [--rig arm|hand] [--steps N] [--layers all|none|sph,metaballs,barnet,anatomy]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <vector>

#include "hal/sim/sweep.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/builtin_layers.hpp"
#include "sim_core/pipeline/pipeline.hpp"

namespace {

bool parse_layers(const std::string& text, sinew::pipeline::PipelineOptions* o, std::string* error) {
  o->sph = o->metaballs = o->barnet = o->anatomy = text == "all";
  if (text == "all" || text == "none") return true;
  std::stringstream list(text);
  for (std::string name; std::getline(list, name, ',');) {
    if (name == "sph")
      o->sph = true;
    else if (name == "metaballs")
      o->metaballs = true;
    else if (name == "barnet")
      o->barnet = true;
    else if (name == "anatomy")
      o->anatomy = true;
    else
      return *error = "--layers: unknown layer '" + name + "' (sph, metaballs, barnet, anatomy)", false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sinew-run: run the pipeline on a built-in rig"};
  std::string rig_name = "arm", layers = "none";
  int steps = 5000;
  app.add_option("--rig", rig_name, "built-in rig")->check(CLI::IsMember({"arm", "hand"}));
  app.add_option("--steps", steps, "pipeline steps")->check(CLI::Range(1, 10000000));
  app.add_option("--layers", layers, "all, none, or a comma list of sph, metaballs, barnet, anatomy");
  CLI11_PARSE(app, argc, argv);

  namespace det = sinew::determinism;
  using namespace sinew;
  pipeline::PipelineOptions options;
  std::string error;
  std::vector<uint8_t> bytes;
  std::vector<std::string> report;
  if (!parse_layers(layers, &options, &error) || !layers::compile_builtin(rig_name, &bytes, &report, &error)) {
    std::fprintf(stderr, "sinew-run: %s\n", error.c_str());
    return 1;
  }
  std::printf("rig %s: blob %zu B\n", rig_name.c_str(), bytes.size());
  for (const std::string& line : report) std::printf("  layer %s\n", line.c_str());

  // Memory is sized once from the rig; the loop below never allocates.
  std::vector<uint64_t> blob(bytes.size() / 8 + 1), rig_arena, layer_arena, state;
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(blob.data());
  size_t rig_bytes = 0, layer_bytes = 0;
  rig::Rig rig;
  pipeline::LayerSet set;
  rig::LoadStatus st = rig::rig_validate(data, bytes.size(), &rig_bytes);
  rig_arena.resize(rig_bytes / 8 + 1);
  if (st.ok()) st = rig::rig_init(data, bytes.size(), rig_arena.data(), rig_arena.size() * 8, &rig);
  if (st.ok()) st = pipeline::layers_validate(rig, data, bytes.size(), &layer_bytes);
  layer_arena.resize(layer_bytes / 8 + 1);
  if (st.ok()) st = pipeline::layers_init(rig, data, bytes.size(), layer_arena.data(), layer_arena.size() * 8, &set);
  if (!st.ok()) {
    std::fprintf(stderr, "sinew-run: %s\n", st.message);
    return 1;
  }
  state.resize(pipeline::pipeline_state_bytes(rig, set, options) / 8 + 1);
  static pipeline::Pipeline p;  // stays where it was initialised
  const pipeline::PipelineStatus ps = pipeline::pipeline_init(rig, set, options, state.data(), state.size() * 8, &p);
  if (!ps.ok()) {
    std::fprintf(stderr, "sinew-run: %s\n", ps.message);
    return 1;
  }
  std::vector<int32_t> inputs(p.input_count, 0);  // external inputs (forces) stay 0
  std::vector<double> step_us(static_cast<size_t>(steps));
  double stage_us[pipeline::kStageCount] = {};
  det::OutputHash hash;
  uint64_t clamped = 0, layer_errors = 0;
  for (int s = 0; s < steps; ++s) {
    for (uint32_t i = 0; i < rig.input_count; ++i) inputs[i] = hal::sim::sweep_input(i, static_cast<uint32_t>(s));
    const auto t0 = std::chrono::steady_clock::now();
    for (uint32_t k = 0; k < pipeline::kStageCount; ++k) {
      const auto stage = static_cast<pipeline::Stage>(k);
      if (!pipeline::pipeline_stage_on(p, stage)) continue;
      const auto a = std::chrono::steady_clock::now();
      layer_errors += pipeline::pipeline_run_stage(&p, stage, inputs).ok() ? 0u : 1u;
      stage_us[k] += std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - a).count();
    }
    step_us[static_cast<size_t>(s)] =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    clamped += p.engine.stats.clamped_dofs;
    for (int c = 0; c < 3; ++c)
      for (uint32_t v = 0; v < rig.vertex_count(); ++v) hash.add_i32(p.engine.vertices.position[c][v]);
  }
  std::sort(step_us.begin(), step_us.end());
  const auto pct = [&](double q) { return step_us[static_cast<size_t>(q * (static_cast<double>(steps) - 1))]; };
  std::printf("steps %d: step time p50 %.1f us, p99 %.1f us, max %.1f us (%.1f%% of a 1 kHz tick at p99)\n", steps,
              pct(0.5), pct(0.99), step_us.back(), pct(0.99) / 10.0);
  std::printf("mean per stage:");
  for (uint32_t k = 0; k < pipeline::kStageCount; ++k)
    if (pipeline::pipeline_stage_on(p, static_cast<pipeline::Stage>(k)))
      std::printf(" %s %.1f us;", pipeline::stage_name(static_cast<pipeline::Stage>(k)),
                  stage_us[k] / static_cast<double>(steps));
  std::printf("\nclamped DOF events %llu, saturated values in the last step %u, layer errors %llu\n",
              static_cast<unsigned long long>(clamped), p.engine.stats.saturated,
              static_cast<unsigned long long>(layer_errors));
  det::print_determinism_line(("run-" + rig_name).c_str(), hash.digest());
  return layer_errors == 0 ? 0 : 1;
}
