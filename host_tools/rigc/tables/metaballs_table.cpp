#include "metaballs_table.hpp"

#include <cmath>
#include <cstdint>
#include <optional>

#include "host_tools/rigc/toml_reader.hpp"

namespace sinew::rigc {

using namespace spec_read;

namespace {

// The [metaballs] table (docs/metaballs.md, "TOML keys"); the builder checks
// the ranges (metaballs_build::check_options).
bool read_metaballs(const std::string& path, const toml::table& e, layers::MetaballsTable* out, std::string* error) {
  metaballs_build::Options& o = out->options;
  const std::string n = "[metaballs]";
  if (!known_keys(
          path, e, n,
          {"ball_spacing", "pbd_iterations", "stretch_stiffness", "jiggle_damping", "jiggle_stretch_stiffness",
           "jiggle_frequency", "jiggle_window", "jiggle_coupling", "overlap_reach", "overlap_between_bones",
           "smoothing_passes", "smoothing_rate", "joint_inner", "joint_outer", "jiggle", "bulge", "action_line"},
          error) ||
      !read_number(path, e, n, "ball_spacing", &out->ball_spacing, error) ||
      !read_int(path, e, n, "pbd_iterations", 0, 16, &o.pbd_iterations, error) ||
      !read_number(path, e, n, "stretch_stiffness", &o.stretch_stiffness, error) ||
      !read_number(path, e, n, "jiggle_damping", &o.jiggle_damping, error) ||
      !read_number(path, e, n, "jiggle_stretch_stiffness", &o.jiggle_stretch_stiffness, error) ||
      !read_number(path, e, n, "jiggle_frequency", &o.jiggle_frequency, error) ||
      !read_number(path, e, n, "jiggle_window", &o.jiggle_window, error) ||
      !read_number(path, e, n, "jiggle_coupling", &o.jiggle_coupling, error) ||
      !read_number(path, e, n, "overlap_reach", &o.overlap_reach, error) ||
      !read_bool(path, e, n, "overlap_between_bones", &o.overlap_between_bones, error) ||
      !read_int(path, e, n, "smoothing_passes", 0, 8, &o.smoothing_passes, error) ||
      !read_number(path, e, n, "smoothing_rate", &o.smoothing_rate, error) ||
      !read_number(path, e, n, "joint_inner", &o.joint_inner, error) ||
      !read_number(path, e, n, "joint_outer", &o.joint_outer, error))
    return false;
  const auto jiggle = [&](const toml::table& t) {
    const std::string label = "[[metaballs.jiggle]]";
    metaballs_build::JiggleRegion r;
    if (!known_keys(path, t, label, {"bone", "from", "to", "stiffness"}, error) ||
        !read_string(path, t, label, "bone", &r.bone, error) || !read_number(path, t, label, "from", &r.from, error) ||
        !read_number(path, t, label, "to", &r.to, error) ||
        !read_number(path, t, label, "stiffness", &r.stiffness, error))
      return false;
    o.jiggle.push_back(r);
    return true;
  };
  const auto bulge = [&](const toml::table& t) {
    const std::string label = "[[metaballs.bulge]]";
    metaballs_build::BulgeRegion r;
    if (!known_keys(path, t, label, {"bone", "from", "to", "angle_a", "angle_b", "gain"}, error) ||
        !read_string(path, t, label, "bone", &r.bone, error) || !read_number(path, t, label, "from", &r.from, error) ||
        !read_number(path, t, label, "to", &r.to, error) ||
        !read_string(path, t, label, "angle_a", &r.angle_a, error) ||
        !read_string(path, t, label, "angle_b", &r.angle_b, error) ||
        !read_number(path, t, label, "gain", &r.gain, error))
      return false;
    o.bulge.push_back(r);
    return true;
  };
  const auto action_line = [&](const toml::table& t) {
    const std::string label = "[[metaballs.action_line]]";
    metaballs_build::ActionLineSpec l;
    if (!known_keys(path, t, label, {"origin", "origin_at", "insertion", "insertion_at", "side", "reach", "stiffness"},
                    error) ||
        !read_string(path, t, label, "origin", &l.origin, error) ||
        !read_number(path, t, label, "origin_at", &l.origin_at, error) ||
        !read_string(path, t, label, "insertion", &l.insertion, error) ||
        !read_number(path, t, label, "insertion_at", &l.insertion_at, error) ||
        !read_number(path, t, label, "reach", &l.reach, error) ||
        !read_number(path, t, label, "stiffness", &l.stiffness, error))
      return false;
    if (!read_vec3(path, t, label, "side", l.side, error)) return false;
    o.action_lines.push_back(l);
    return true;
  };
  return each_table(path, e, "jiggle", jiggle, error, "metaballs") &&
         each_table(path, e, "bulge", bulge, error, "metaballs") &&
         each_table(path, e, "action_line", action_line, error, "metaballs");
}

}  // namespace

bool RigcTable<pipeline::Stage::kMetaballs>::read(const std::string& path, const toml::table& root, Tables* out,
                                                  std::string* error) {
  return single_table(
      path, root, "metaballs", &out->on, &out->where,
      [&](const toml::table& e) { return read_metaballs(path, e, out, error); }, error);
}

}  // namespace sinew::rigc
