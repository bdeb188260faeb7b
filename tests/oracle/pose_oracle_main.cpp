// sinew-pose-oracle MODEL.gltf|.glb --animation N --time SECONDS [--time ...] --out FILE.csv
// The double-precision reference's skinned vertex positions, in the same CSV
// format as sinew-pose (comment lines, then x,y,z with 9 significant digits),
// so the two can be compared by hand.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>

#include "gltf_oracle.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sinew-pose-oracle: double-precision reference positions of a glTF skin"};
  std::string model, out_path;
  int animation = 0;
  std::vector<double> times;
  app.add_option("model", model, "glTF 2.0 file (.gltf or .glb) with a skin")->required();
  app.add_option("--animation", animation, "animation index (0-based; -1 = rest pose)")->check(CLI::Range(-1, 1 << 30));
  app.add_option("--time", times, "time in seconds (repeatable; clamped to each sampler's keyframes)")->required();
  app.add_option("--out", out_path, "output CSV file")->required();
  CLI11_PARSE(app, argc, argv);

  std::ofstream out(out_path);
  if (!out) {
    std::fprintf(stderr, "sinew-pose-oracle: cannot write %s\n", out_path.c_str());
    return 1;
  }
  out << "# sinew-pose-oracle " << model << " animation " << animation << "\n";
  bool first = true;
  for (double t : times) {
    sinew::oracle::OracleResult result;
    std::string error;
    if (!sinew::oracle::skinned_pose(model, animation, t, &result, &error)) {
      std::fprintf(stderr, "sinew-pose-oracle: %s\n", error.c_str());
      return 1;
    }
    if (first) {
      char line[160];
      std::snprintf(line, sizeof(line),
                    "# double-precision glTF 2.0 reference; rest bbox diagonal %.9g; "
                    "renormalised weights %d\n",
                    result.bbox_diagonal, result.renormalized_vertices);
      out << line;
      first = false;
    }
    out << "# time " << t << " s, " << result.positions.size() << " vertices: x,y,z\n";
    char line[96];
    for (const Eigen::Vector3d& p : result.positions) {
      std::snprintf(line, sizeof(line), "%.9g,%.9g,%.9g\n", p.x(), p.y(), p.z());
      out << line;
    }
  }
  return out.good() ? 0 : 1;
}
