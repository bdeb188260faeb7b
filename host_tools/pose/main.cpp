// sinew-pose MODEL.gltf|.glb --animation N --time SECONDS [--time ...] --out FILE.csv
// Samples a glTF animation and writes the deformed vertex positions of every
// skinned primitive (glTF document order, glTF vertex order, glTF units,
// skinned world space) computed by sinew's fixed-point pipeline.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>

#include "host_tools/rigc/gltf_poser.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sinew-pose: deformed vertex positions of a glTF skin, through the fixed-point pipeline"};
  std::string model, out_path;
  int animation = 0;
  std::vector<double> times;
  app.add_option("model", model, "glTF 2.0 file (.gltf or .glb) with a skin")->required();
  app.add_option("--animation", animation, "animation index (0-based)")->check(CLI::NonNegativeNumber);
  app.add_option("--time", times, "time in seconds (repeatable; clamped to the animation's range)")->required();
  app.add_option("--out", out_path, "output CSV file")->required();
  CLI11_PARSE(app, argc, argv);

  sinew::rigc::GltfPoser poser;
  std::string error;
  if (!poser.open(model, &error)) {
    std::fprintf(stderr, "sinew-pose: %s\n", error.c_str());
    return 1;
  }
  std::ofstream out(out_path);
  if (!out) {
    std::fprintf(stderr, "sinew-pose: cannot write %s\n", out_path.c_str());
    return 1;
  }
  out << "# sinew-pose " << model << " animation " << animation << "\n";
  out << "# " << sinew::rigc::format_report(poser.report()) << "\n";
  for (double t : times) {
    std::vector<std::array<double, 3>> positions;
    if (!poser.pose(animation, t, &positions, &error)) {
      std::fprintf(stderr, "sinew-pose: %s\n", error.c_str());
      return 1;
    }
    out << "# time " << t << " s, " << positions.size() << " vertices: x,y,z\n";
    char line[96];
    for (const auto& p : positions) {
      std::snprintf(line, sizeof(line), "%.9g,%.9g,%.9g\n", p[0], p[1], p[2]);
      out << line;
    }
  }
  if (poser.report().renormalized_vertices > 0)
    std::fprintf(stderr, "sinew-pose: note: %u vertices had weights not summing to 1; renormalised\n",
                 poser.report().renormalized_vertices);
  return out.good() ? 0 : 1;
}
