// sinew-builtin-rig NAME OUT.rig: compiles a built-in rig with its layers
// (builtin_layers.hpp) into a blob at build time; the firmware embeds it.
// Runs on the build machine, or under the cross build's emulator: the blob
// is bit-identical on every platform (the golden tests pin its hash).
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/layers/builtin_layers.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: sinew-builtin-rig NAME OUT.rig\n");
    return 2;
  }
  std::vector<uint8_t> blob;
  std::vector<std::string> report;
  std::string error;
  if (!sinew::layers::compile_builtin(argv[1], &blob, &report, &error)) {
    std::fprintf(stderr, "sinew-builtin-rig: %s\n", error.c_str());
    return 1;
  }
  const std::string tmp = std::string(argv[2]) + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(blob.data()), static_cast<std::streamsize>(blob.size()));
    f.close();
    if (!f) {
      std::fprintf(stderr, "sinew-builtin-rig: cannot write %s\n", tmp.c_str());
      return 1;
    }
  }
  if (std::rename(tmp.c_str(), argv[2]) != 0) {
    std::fprintf(stderr, "sinew-builtin-rig: cannot rename %s\n", tmp.c_str());
    return 1;
  }
  return 0;
}
