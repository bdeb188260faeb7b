// sinew-pose MODEL.gltf|.glb --animation N --time SECONDS [--time ...] --out FILE.csv
// sinew-pose MODEL.gltf|.glb --bind-pose --out FILE.csv
// sinew-pose --spec SPEC.toml --animation N --time SECONDS --out FILE.csv
//   (the spec's [rig] source is the model; its layer tables run too)
// sinew-pose --spec SPEC.toml --motion TAKE.bvh|TRACKS.csv --time SECONDS --out FILE.csv
//   (a motion file drives the rig's inputs; the source may be built in)
// Any of these with --glb FILE.glb (and --out optional): the same poses as a
// glTF binary (docs/export.md): without --time, the whole animation or
// motion sampled at --fps.
// Samples a glTF animation (or takes the bind pose: every node at its default
// transform) and writes the deformed vertex positions of every skinned
// primitive (glTF document order, glTF vertex order, glTF units, skinned world
// space) computed by sinew's fixed-point pipeline. The CSV is written whole or
// not at all.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "host_tools/common/guarded_main.hpp"
#include "host_tools/export/clip_glb.hpp"
#include "host_tools/export/rig_clip.hpp"
#include "host_tools/rigc/gltf_poser.hpp"
#include "host_tools/rigc/output_file.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "sinew-pose: %s\n", message.c_str());
  return 1;
}

void append_positions(const std::vector<std::array<double, 3>>& positions, std::string* csv) {
  char line[96];
  for (const auto& p : positions) {
    std::snprintf(line, sizeof(line), "%.9g,%.9g,%.9g\n", p[0], p[1], p[2]);
    *csv += line;
  }
}

// The pose the poser holds, as the next frame of the clip.
void capture_frame(const sinew::rigc::GltfPoser& poser, double time_s, sinew::gltf_export::SurfaceClip* clip) {
  const sinew::engine::Engine& engine = poser.posed_engine();
  sinew::gltf_export::FixedFrame frame;
  for (int c = 0; c < 3; ++c) {
    frame.position[c] = engine.vertices.position[c];
    frame.normal[c] = engine.vertices.normal[c];
  }
  sinew::gltf_export::append_frame(poser.rig(), time_s, frame, engine.locals, clip);
}

// Without --time, a glb samples the whole animation (or motion) at fps.
bool glb_times(const sinew::rigc::GltfPoser& poser, bool with_motion, int animation, double fps,
               std::vector<double>* times, std::string* error) {
  double start = 0, end = 0;
  if (with_motion) {
    start = poser.motion_tracks().times.front(), end = poser.motion_tracks().times.back();
  } else if (!sinew::rigc::animation_range(poser.model(), animation, &start, &end, error)) {
    return false;
  }
  const double frames = std::floor((end - start) * fps + 1e-9) + 1;
  if (frames > sinew::gltf_export::kMaxExportFrames)
    return *error = "--glb: " + std::to_string(static_cast<uint64_t>(frames)) + " frames at --fps " +
                    std::to_string(fps) + "; lower --fps or give --time values",
           false;
  for (double k = 0; k < frames; ++k) times->push_back(start + k / fps);
  return true;
}

int run(int argc, char** argv) {
  CLI::App app{"sinew-pose: deformed vertex positions of a glTF skin, through the fixed-point pipeline"};
  std::string model, out_path, spec, motion_path;
  uint32_t tick_hz = 100;
  int animation = 0;
  bool bind_pose = false;
  std::vector<double> times;
  auto* model_opt = app.add_option("model", model, "glTF 2.0 file (.gltf or .glb) with a skin");
  app.add_option("--spec", spec,
                 "rig spec (TOML) whose [rig] source is the model: the animation is played through every layer "
                 "its tables ask for")
      ->excludes(model_opt);
  app.add_option("--rate", tick_hz,
                 "with --spec: tick rate (Hz) the animation is simulated at, from its start to each time")
      ->check(CLI::Range(13u, 100000u));
  auto* anim_opt = app.add_option("--animation", animation, "animation index (0-based)")->check(CLI::NonNegativeNumber);
  auto* time_opt =
      app.add_option("--time", times, "time in seconds (repeatable; clamped to the animation's range; finite)");
  auto* bind_opt =
      app.add_flag("--bind-pose", bind_pose, "write the bind pose (every node at its default transform), no animation")
          ->excludes(anim_opt)
          ->excludes(time_opt);
  app.add_option("--motion", motion_path,
                 "with --spec: play a motion file instead of an animation: BVH (.bvh; joints by the rig's names or "
                 "the spec's [motion.bvh_joints]) or CSV joint tracks (time, <joint>.<dof> in degrees)")
      ->excludes(anim_opt)
      ->excludes(bind_opt);
  std::string glb_path;
  double fps = 30;
  app.add_option("--out", out_path, "output CSV file");
  app.add_option("--glb", glb_path,
                 "also write the poses as a glTF binary (morph-target surface and skeleton animation); without "
                 "--time, the whole animation or motion at --fps");
  app.add_option("--fps", fps, "with --glb and no --time: frames per second sampled")->check(CLI::Range(0.1, 1000.0));
  CLI11_PARSE(app, argc, argv);
  if (out_path.empty() && glb_path.empty()) return fail("give --out FILE.csv, --glb FILE.glb, or both");
  if (!bind_pose && times.empty() && glb_path.empty()) return fail("give --time SECONDS (repeatable) or --bind-pose");
  for (double t : times)
    if (!std::isfinite(t)) return fail("--time " + std::to_string(t) + " is not a finite number of seconds");

  if (model.empty() && spec.empty()) return fail("give a MODEL.gltf|.glb or --spec SPEC.toml");
  if (!motion_path.empty() && spec.empty()) return fail("--motion needs --spec SPEC.toml (the rig it drives)");
  const bool with_motion = !motion_path.empty();
  sinew::rigc::GltfPoser poser;
  std::string error;
  if (!(spec.empty() ? poser.open(model, &error) : poser.open_spec(spec, tick_hz, &error, !with_motion)))
    return fail(error);
  if (with_motion && !poser.set_motion(motion_path, &error)) return fail(error);
  if (!spec.empty()) model = spec;
  const sinew::rigc::CompileReport& report = poser.report();
  if (report.length_exponent_clamped)
    std::fprintf(stderr,
                 "sinew-pose: warning: the largest coordinate (%g) is outside what the rig unit can represent; "
                 "the unit was clamped to 2^%d and positions are saturated or coarse\n",
                 report.extent, report.length_exponent);
  if (!bind_pose && !with_motion && poser.model().animations.empty())
    return fail(model + " has no animations; use --bind-pose for its bind pose");

  if (!glb_path.empty() && !bind_pose && times.empty() &&
      !glb_times(poser, with_motion, animation, fps, &times, &error))
    return fail(error);
  for (size_t k = 1; !glb_path.empty() && k < times.size(); ++k)
    if (!(times[k] > times[k - 1])) return fail("--glb: the --time values must increase");
  const bool with_glb = !glb_path.empty();
  sinew::gltf_export::SurfaceClip clip;
  clip.generator = "sinew-pose";
  if (with_glb) sinew::gltf_export::set_rest_from_rig(poser.rig(), &clip);
  clip.notes = {{"source", model},
                {"played", bind_pose     ? "bind pose"
                           : with_motion ? motion_path
                                         : "animation " + std::to_string(animation)}};

  // Every pose first, so that a failure leaves no partial CSV behind.
  std::string csv = "# sinew-pose " + model +
                    (bind_pose     ? " bind pose"
                     : with_motion ? " motion " + motion_path
                                   : " animation " + std::to_string(animation)) +
                    "\n# " + sinew::rigc::format_report(report) + "\n";
  for (const std::string& line : poser.layer_report()) csv += "# layer " + line + "\n";
  std::vector<std::array<double, 3>> positions;
  if (bind_pose) {
    if (!poser.pose(-1, 0.0, &positions, &error)) return fail(error);
    if (with_glb) capture_frame(poser, 0.0, &clip);
    csv += "# bind pose, " + std::to_string(positions.size()) + " vertices: x,y,z\n";
    append_positions(positions, &csv);
  }
  for (double t : times) {
    if (!(with_motion ? poser.pose_motion(t, &positions, &error) : poser.pose(animation, t, &positions, &error)))
      return fail(error);
    if (with_glb && !bind_pose) capture_frame(poser, t - times.front(), &clip);
    char head[96];
    std::snprintf(head, sizeof(head), "# time %g s, %zu vertices: x,y,z\n", t, positions.size());
    csv += head;
    append_positions(positions, &csv);
  }
  if (with_glb) {
    std::vector<uint8_t> glb;
    if (!sinew::gltf_export::encode_clip_glb(clip, &glb, &error)) return fail(glb_path + ": " + error);
    const std::string_view bytes(reinterpret_cast<const char*>(glb.data()), glb.size());
    if (!sinew::rigc::write_output_file(glb_path, bytes, &error)) return fail(error);
  }
  if (!out_path.empty() && !sinew::rigc::write_output_file(out_path, csv, &error)) return fail(error);
  if (report.renormalized_vertices > 0)
    std::fprintf(stderr, "sinew-pose: note: %u vertices had weights not summing to 1; renormalised\n",
                 report.renormalized_vertices);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return sinew::host::guarded_main("sinew-pose", run, argc, argv); }
