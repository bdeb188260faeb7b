#include "barnet_table.hpp"

#include <cmath>
#include <cstdint>
#include <optional>

#include "host_tools/rigc/toml_reader.hpp"

namespace sinew::rigc {

using namespace spec_read;

bool RigcTable<pipeline::Stage::kBarnet>::read(const std::string& path, const toml::table& root, Tables* out,
                                               std::string* error) {
  return each_table(
      path, root, "barnet",
      [&](const toml::table& e) {
        layers::BarnetTable x;
        const std::string n = "[[barnet]]";
        if (!known_keys(path, e, n,
                        {"joint", "net", "segments", "rings", "ring_step", "force", "force_input", "force_input_full",
                         "q_input"},
                        error) ||
            !read_joint(path, e, n, "joint", &x.joint, error) ||
            !read_int(path, e, n, "segments", 3, 32, &x.segments, error) ||
            !read_int(path, e, n, "rings", 5, 15, &x.rings, error) ||
            !read_number(path, e, n, "ring_step", &x.ring_step, error) ||
            !read_number(path, e, n, "force", &x.force, error) ||
            !read_string(path, e, n, "force_input", &x.force_input, error) ||
            !read_number(path, e, n, "force_input_full", &x.force_input_full, error) ||
            !read_string(path, e, n, "q_input", &x.q_input, error) || !read_string(path, e, n, "net", &x.net, error))
          return false;
        if (x.net != "joint" && x.net != "muscles" && x.net != "wrinkles" && x.net != "arm-muscles" &&
            x.net != "arm-wrinkles")
          return *error = x.joint.where +
                          ": net must be \"joint\", \"muscles\", \"wrinkles\", \"arm-muscles\" or "
                          "\"arm-wrinkles\"",
                 false;
        if (x.net == "muscles" && x.segments % 2 != 0)
          return *error = x.joint.where + ": segments must be even for net = \"muscles\"", false;
        if (x.ring_step < 0 || x.force < 0) return *error = x.joint.where + ": ring_step and force must be >= 0", false;
        if (!(x.force_input_full != 0 && std::fabs(x.force_input_full) <= 32767))
          return *error = x.joint.where + ": force_input_full must be non-zero, within +-32767", false;
        out->push_back(x);
        return true;
      },
      error);
}

}  // namespace sinew::rigc
