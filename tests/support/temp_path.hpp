// A file name in the system's temporary directory that belongs to this test
// process alone. ctest runs every test in a process of its own, several at
// a time (-j), so two tests of one binary that write the same fixed name
// race: one removes or rewrites the other's file between its write and its
// read.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace sinew::test {

inline std::string process_temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("sinew_" + std::to_string(::getpid()) + "_" + name)).string();
}

}  // namespace sinew::test
