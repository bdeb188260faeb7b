// sinew-run: the main job on a built-in rig. Compiles the rig in-process,
// steps the engine over the built-in joint trajectory, and prints the rig
// summary, step-time statistics and the determinism hash of the outputs.
//   sinew-run [--rig arm|hand] [--steps N]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

#include "host_tools/determinism/engine_workload.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/engine/engine.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sinew-run: run the engine on a built-in rig"};
  std::string rig_name = "arm";
  int steps = 5000;
  app.add_option("--rig", rig_name, "built-in rig")->check(CLI::IsMember({"arm", "hand"}));
  app.add_option("--steps", steps, "engine steps")->check(CLI::Range(1, 10000000));
  CLI11_PARSE(app, argc, argv);

  namespace det = sinew::determinism;
  using namespace sinew;
  rigc::RigSpec spec;
  rigc::builtin_rig(rig_name, rigc::SkinChoice::kDualQuaternion, &spec);
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  if (!rigc::compile_rig(spec, &bytes, &report, &error)) {
    std::fprintf(stderr, "sinew-run: %s\n", error.c_str());
    return 1;
  }
  std::printf("rig %s: %s\n", rig_name.c_str(), rigc::format_report(report).c_str());

  // Memory is sized once from the rig; the loop below never allocates.
  std::vector<uint64_t> blob(bytes.size() / 8 + 1), rig_arena, engine_arena;
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(blob.data());
  size_t rig_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(data, bytes.size(), &rig_bytes);
  rig_arena.resize(rig_bytes / 8 + 1);
  rig::Rig rig;
  if (st.ok()) st = rig::rig_init(data, bytes.size(), rig_arena.data(), rig_arena.size() * 8, &rig);
  if (!st.ok()) {
    std::fprintf(stderr, "sinew-run: %s\n", st.message);
    return 1;
  }
  engine_arena.resize(engine::engine_arena_bytes(rig) / 8 + 1);
  engine::Engine e;
  engine::engine_init(rig, engine_arena.data(), engine_arena.size() * 8, &e);
  std::vector<int32_t> inputs(rig.input_count);
  std::vector<double> step_us(static_cast<size_t>(steps));
  det::OutputHash hash;
  uint64_t clamped = 0;
  for (int s = 0; s < steps; ++s) {
    for (uint32_t i = 0; i < rig.input_count; ++i) inputs[i] = det::trajectory_input(i, static_cast<uint32_t>(s));
    const auto t0 = std::chrono::steady_clock::now();
    engine::engine_step(&e, inputs);
    step_us[static_cast<size_t>(s)] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    clamped += e.stats.clamped_dofs;
    for (int c = 0; c < 3; ++c)
      for (uint32_t v = 0; v < rig.vertex_count(); ++v) hash.add_i32(e.vertices.position[c][v]);
  }
  std::sort(step_us.begin(), step_us.end());
  const auto pct = [&](double p) { return step_us[static_cast<size_t>(p * (static_cast<double>(steps) - 1))]; };
  std::printf("steps %d: step time p50 %.1f us, p99 %.1f us, max %.1f us (%.1f%% of a 1 kHz tick at p99)\n", steps,
              pct(0.5), pct(0.99), step_us.back(), pct(0.99) / 10.0);
  std::printf("clamped DOF events %llu, saturated values in the last step %u\n",
              static_cast<unsigned long long>(clamped), e.stats.saturated);
  det::print_determinism_line(("run-" + rig_name).c_str(), hash.digest());
  return 0;
}
