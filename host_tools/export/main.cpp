// sinew-export FRAMELOG --rig FILE|NAME -o RUN.glb [--from S] [--to S] [--every N]
// Writes a frame log's run as a glTF 2.0 binary: the deformed surface as
// morph targets played by a weights animation, and the skeleton as a node
// animation (docs/export.md). The file is written whole or not at all.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "clip_glb.hpp"
#include "frame_log_clip.hpp"
#include "hal/common/safe_create.hpp"
#include "host_tools/common/guarded_main.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "sinew-export: %s\n", message.c_str());
  return 1;
}

// "builtin:arm", or "arm" / "hand" when no file of that name exists, is a
// built-in rig; anything else is a rig blob file.
bool load_named_rig(const std::string& rig, sinew::firmware::LoadedRig* out, std::string* error) {
  std::string builtin;
  if (rig.rfind("builtin:", 0) == 0)
    builtin = rig.substr(8);
  else if ((rig == "arm" || rig == "hand") && !std::filesystem::exists(rig))
    builtin = rig;
  return sinew::firmware::load_rig(builtin, builtin.empty() ? rig : "", out, error);
}

int run(int argc, char** argv) {
  CLI::App app{"sinew-export: a frame log's run as a glTF 2.0 binary (morph-target surface, skeleton animation)"};
  std::string log_path, rig_name, out_path;
  sinew::gltf_export::LogSelection selection;
  app.add_option("framelog", log_path, "frame log written by sinewd or sinew-log render")->required();
  app.add_option("--rig", rig_name, "the run's rig: a blob file, or a built-in name (arm, hand, builtin:arm)")
      ->required();
  app.add_option("-o,--out", out_path, "output .glb file (replaced whole, or left untouched on failure)")->required();
  app.add_option("--from", selection.from_s, "first time exported, seconds from the log's first frame")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--to", selection.to_s, "last time exported, seconds from the log's first frame")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--every", selection.every, "export every N-th frame of the range")->check(CLI::Range(1u, 1000000u));
  app.add_option("--max-frames", selection.max_frames, "refuse to export more frames than this")
      ->check(CLI::Range(1u, 100000u));
  CLI11_PARSE(app, argc, argv);
  if (selection.from_s > selection.to_s) return fail("--from is after --to");

  sinew::firmware::LoadedRig rig;
  std::string error;
  if (!load_named_rig(rig_name, &rig, &error)) return fail(error);
  sinew::gltf_export::SurfaceClip clip;
  sinew::gltf_export::LogExportReport report;
  if (!sinew::gltf_export::clip_from_frame_log(log_path, rig, selection, &clip, &report, &error)) return fail(error);
  if (!report.stopped_early.empty()) std::fprintf(stderr, "sinew-export: note: %s\n", report.stopped_early.c_str());
  clip.generator = "sinew-export";
  clip.notes.emplace_back("rig", rig_name);
  std::vector<uint8_t> glb;
  if (!sinew::gltf_export::encode_clip_glb(clip, &glb, &error)) return fail(log_path + ": " + error);
  const std::string_view bytes(reinterpret_cast<const char*>(glb.data()), glb.size());
  if (!sinew::hal::write_replacing(out_path, "glTF file", bytes, 0666, &error)) return fail(error);
  std::printf(
      "%s: %zu frames (ticks %llu..%llu, %.3f s), %u vertices, %zu joints, normals %s; %zu bytes (%.0f per frame)\n",
      out_path.c_str(), clip.frames.size(), static_cast<unsigned long long>(report.first_tick),
      static_cast<unsigned long long>(report.last_tick), report.last_time_s - report.first_time_s, clip.vertex_count(),
      clip.joints.size(), report.has_normals ? "logged" : "derived", glb.size(),
      static_cast<double>(glb.size()) / static_cast<double>(clip.frames.size()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return sinew::host::guarded_main("sinew-export", run, argc, argv); }
