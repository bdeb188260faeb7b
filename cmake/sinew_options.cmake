# Project-wide compile settings.

if(SINEW_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

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
