# Project-wide compile settings.

# ccache, when installed, makes a rebuild of unchanged sources (another preset's
# clone, a second checkout) a cache hit. Paths are rewritten relative to the
# source tree (CCACHE_BASEDIR, and no working directory in the hash), so a fresh
# clone elsewhere hits the cache of an earlier one. SINEW_CCACHE=OFF turns it off
# (e.g. to time a cold build).
option(SINEW_CCACHE "Compile through ccache when it is installed" ON)
find_program(SINEW_CCACHE_PROGRAM ccache)
if(SINEW_CCACHE AND SINEW_CCACHE_PROGRAM AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_CXX_COMPILER_LAUNCHER
      ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR} CCACHE_NOHASHDIR=1 ${SINEW_CCACHE_PROGRAM})
endif()

if(SINEW_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

# Files whose compile time under the sanitizers far exceeds what their
# speed is worth compile unoptimised in sanitized builds; the sanitizers
# still instrument them (docs/testing.md, "CI time"). The command-line
# entry points (the daemon's and the tools' main files): CLI11 is
# header-only, every file that includes it generates its whole parser, and
# under UBSan at -O1 that takes about 35 s a file against 13 s at -O0, for
# code that runs once per process and hands over to the optimised
# libraries. Third-party implementation files (tinygltf with its JSON
# parser): the largest single file of the build, parsing a few small files
# per test.
function(sinew_unoptimised_when_sanitized)
  if(SINEW_SANITIZE)
    set_source_files_properties(${ARGN} DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} PROPERTIES COMPILE_OPTIONS -O0)
  endif()
endfunction()

# Strict warnings for sim_core and everything the project writes itself.
set(SINEW_STRICT_WARNINGS
    -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow
    -Wold-style-cast -Wcast-align -Wnull-dereference -Werror)

# sim_core has no exceptions and needs no RTTI.
set(SINEW_CORE_FLAGS -fno-exceptions -fno-rtti)

function(sinew_strict target)
  target_compile_options(${target} PRIVATE ${SINEW_STRICT_WARNINGS})
endfunction()

# GoogleTest: the distribution's package natively; built from Debian's source
# package (googletest) when cross compiling, where no target libgtest exists.
function(sinew_find_gtest)
  if(TARGET GTest::gtest_main)
    return()
  endif()
  if(CMAKE_CROSSCOMPILING)
    set(gtest_src /usr/src/googletest)
    if(NOT EXISTS ${gtest_src}/CMakeLists.txt)
      message(FATAL_ERROR "googletest sources not found at ${gtest_src}: install Debian's 'googletest' package")
    endif()
    set(INSTALL_GTEST OFF CACHE BOOL "" FORCE)
    set(BUILD_GMOCK OFF CACHE BOOL "" FORCE)
    add_subdirectory(${gtest_src} ${CMAKE_BINARY_DIR}/_googletest EXCLUDE_FROM_ALL)
    if(NOT TARGET GTest::gtest_main)  # googletest >= 1.11 defines these itself
      add_library(GTest::gtest ALIAS gtest)
      add_library(GTest::gtest_main ALIAS gtest_main)
    endif()
  else()
    find_package(GTest REQUIRED)
  endif()
endfunction()
