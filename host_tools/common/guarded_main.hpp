// The main() of a command-line tool: runs the tool and turns an exception
// that escapes it (a bug: every expected failure returns its own message)
// into "<tool>: internal error: <what>" on stderr and exit status 1, instead
// of std::terminate's abort.
#pragma once

#include <cstdio>
#include <exception>

namespace sinew::host {

// tool: the name the messages start with. run: the tool's body.
inline int guarded_main(const char* tool, int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", tool, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: internal error\n", tool);
  }
  return 1;
}

}  // namespace sinew::host
