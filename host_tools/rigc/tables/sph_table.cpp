#include "sph_table.hpp"

#include <cmath>
#include <cstdint>
#include <optional>

#include "host_tools/rigc/toml_reader.hpp"

namespace sinew::rigc {

using namespace spec_read;

bool RigcTable<pipeline::Stage::kSph>::read(const std::string& path, const toml::table& root, Tables* out,
                                            std::string* error) {
  return each_table(
      path, root, "sph",
      [&](const toml::table& e) {
        layers::SphTable x;
        const std::string n = "[[sph]]";
        if (!known_keys(path, e, n,
                        {"joint", "particles", "radius", "half_length", "tissue_mass", "yield_angle", "force_input",
                         "surface_tension"},
                        error) ||
            !read_joint(path, e, n, "joint", &x.joint, error) ||
            !read_int(path, e, n, "particles", 8, 8192, &x.particles, error) ||
            !read_number(path, e, n, "radius", &x.radius, error) ||
            !read_number(path, e, n, "half_length", &x.half_length, error) ||
            !read_number(path, e, n, "tissue_mass", &x.tissue_mass, error) ||
            !read_number(path, e, n, "yield_angle", &x.yield_angle_deg, error) ||
            !read_string(path, e, n, "force_input", &x.force_input, error) ||
            !read_number(path, e, n, "surface_tension", &x.surface_tension, error))
          return false;
        if (x.radius < 0 || x.half_length < 0 || x.tissue_mass < 0 || x.surface_tension < 0 ||
            !(x.yield_angle_deg >= 0 && x.yield_angle_deg < 180))
          return *error = x.joint.where +
                          ": radius, half_length, tissue_mass, surface_tension must be >= 0 and yield_angle in "
                          "[0, 180) (0: the joint's maximum flexion)",
                 false;
        out->push_back(x);
        return true;
      },
      error);
}

}  // namespace sinew::rigc
