# Usage: cmake -DSIM_CORE_DIR=<dir> -P sim_core_lint.cmake
# Scans every C++ source under SIM_CORE_DIR, ignoring // comments, for
# constructs sim_core must not use.
file(GLOB_RECURSE sources "${SIM_CORE_DIR}/*.hpp" "${SIM_CORE_DIR}/*.cpp" "${SIM_CORE_DIR}/*.h" "${SIM_CORE_DIR}/*.cc")
set(forbidden
  "float:[^A-Za-z0-9_]float[^A-Za-z0-9_]"
  "double:[^A-Za-z0-9_]double[^A-Za-z0-9_]"
  "floating literal:[^A-Za-z0-9_.][0-9]+\\.[0-9]*([eE][-+]?[0-9]+)?[fF]?[^A-Za-z0-9_.]"
  "heap (new):[^A-Za-z0-9_]new[ (]"
  "heap (delete):[^A-Za-z0-9_]delete[ \\[]"
  "heap (malloc family):[^A-Za-z0-9_](malloc|calloc|realloc|free|aligned_alloc)[ ]*\\("
  "heap container:std::(vector|string|map|set|unordered_map|unordered_set|list|deque|function|shared_ptr|unique_ptr|make_unique|make_shared)"
  "exceptions:[^A-Za-z0-9_](throw|try|catch)[^A-Za-z0-9_]"
  "iostreams/stdio:#include <(iostream|fstream|sstream|cstdio|stdio.h|thread|chrono|random|mutex|filesystem)>"
  "OS call:[^A-Za-z0-9_](printf|fprintf|puts|fopen|open|read|write|ioctl|mmap|socket|clock_gettime|sleep|usleep|getenv|exit|abort)[ ]*\\("
  "OS header:#include <(unistd.h|fcntl.h|sys/[a-z_]+.h|pthread.h|time.h|ctime|csignal|signal.h)>"
)
set(violations 0)
foreach(src IN LISTS sources)
  # Read raw text (file(STRINGS) splits at non-ASCII bytes) and protect ';'
  # so a line stays one list element.
  file(READ "${src}" text)
  string(REPLACE ";" "<semicolon>" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    string(REGEX REPLACE "//.*$" "" code " ${line} ")
    foreach(rule IN LISTS forbidden)
      string(FIND "${rule}" ":" colon)
      string(SUBSTRING "${rule}" 0 ${colon} what)
      math(EXPR start "${colon} + 1")
      string(SUBSTRING "${rule}" ${start} -1 regex)
      if(code MATCHES "${regex}")
        message("${src}:${n}: sim_core must not use ${what}: ${line}")
        math(EXPR violations "${violations} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
list(LENGTH sources count)
if(violations GREATER 0)
  message(FATAL_ERROR "sim_core lint: ${violations} violation(s) in ${count} files")
endif()
message("sim_core lint: ${count} files clean")
