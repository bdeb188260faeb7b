// rigc: compiles a rig into sinew's binary format and prints its summary.
//   rigc SPEC.toml -o arm.rig
//   rigc builtin:arm -o arm.rig
//   rigc model.glb -o model.rig
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <string_view>

#include "host_tools/common/guarded_main.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/gltf_import.hpp"
#include "host_tools/rigc/output_file.hpp"
#include "host_tools/rigc/toml_spec.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "rigc: %s\n", message.c_str());
  return 1;
}

int run(int argc, char** argv) {
  CLI::App app{"rigc: compile a rig (TOML spec, glTF 2.0 skin or built-in) into a sinew rig blob"};
  std::string input, output, skinning = "dqs";
  app.add_option("input", input, "SPEC.toml, MODEL.gltf/.glb, builtin:arm or builtin:hand")->required();
  app.add_option("-o,--out", output, "output rig blob");
  app.add_option("--skinning", skinning, "lbs or dqs for built-in rigs")->check(CLI::IsMember({"lbs", "dqs"}));
  CLI11_PARSE(app, argc, argv);

  using namespace sinew::rigc;
  RigSpec spec;
  sinew::layers::LayerSpecs layer_specs;
  std::vector<std::string> layer_report;
  std::string error;
  const SkinChoice method = skinning == "dqs" ? SkinChoice::kDualQuaternion : SkinChoice::kLinear;
  bool ok = false;
  if (input.rfind("builtin:", 0) == 0) {
    ok = builtin_rig(input.substr(8), method, &spec);
    if (!ok) error = input + ": unknown built-in rig (arm, hand)";
  } else if (input.size() > 5 && input.substr(input.size() - 5) == ".toml") {
    ok = load_toml_rig(input, &spec, &layer_specs, &error);
  } else {
    GltfRig gltf;
    ok = import_gltf(input, &gltf, &error);
    spec = gltf.spec;
  }
  std::vector<uint8_t> blob;
  CompileReport report;
  if (ok) ok = sinew::layers::add_layer_dofs(&spec, layer_specs, &layer_report, &error);
  if (ok) ok = compile_rig(spec, &blob, &report, &error);
  if (ok) ok = sinew::layers::compile_layers(spec, layer_specs, &blob, &layer_report, &error);
  if (!ok) return fail(error);
  std::printf("rigc: %s\n", format_report(report).c_str());
  if (report.length_exponent_clamped)
    std::fprintf(stderr,
                 "rigc: warning: the largest coordinate (%g) is outside what the rig unit can represent; "
                 "the unit was clamped to 2^%d and positions are saturated or coarse\n",
                 report.extent, report.length_exponent);
  for (const std::string& line : layer_report) std::printf("rigc: layer %s\n", line.c_str());
  if (!layer_report.empty()) std::printf("rigc: blob with layers %zu B\n", blob.size());
  if (report.renormalized_vertices > 0)
    std::printf("rigc: %u vertices had weights not summing to 1; renormalised\n", report.renormalized_vertices);
  if (!output.empty()) {
    const std::string_view bytes(reinterpret_cast<const char*>(blob.data()), blob.size());
    if (!write_output_file(output, bytes, &error)) return fail(error);
    std::printf("rigc: wrote %s\n", output.c_str());
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) return fail("cannot write the summary to standard output");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return sinew::host::guarded_main("rigc", run, argc, argv); }
