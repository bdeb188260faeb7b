# The stage list (sim_core/pipeline/stage_list.hpp) read by the build, so a
# layer's files are found by their names and no CMake or shared source file
# lists the layers: adding a layer is one line in stage_list.hpp plus its
# own files (docs/architecture.md, "Where a layer goes").

set(SINEW_STAGE_LIST_FILE ${PROJECT_SOURCE_DIR}/sim_core/pipeline/stage_list.hpp)
set(SINEW_GENERATED_DIR ${PROJECT_BINARY_DIR}/generated)
set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${SINEW_STAGE_LIST_FILE})

# out: the stages' names, in the order a tick runs them.
function(sinew_stage_names out)
  # Read whole: its lines end in "\", which would escape a list's ";".
  file(READ ${SINEW_STAGE_LIST_FILE} text)
  string(REGEX MATCHALL "X\\([a-z_]+," entries "${text}")
  set(names "")
  foreach(e IN LISTS entries)
    string(REGEX REPLACE "X\\(([a-z_]+)," "\\1" stage "${e}")
    list(APPEND names ${stage})
  endforeach()
  set(${out} ${names} PARENT_SCOPE)
endfunction()

# out: for each stage, the files PATTERNs name with @stage@ replaced by the
# stage's name, relative to the calling CMakeLists.txt, those that exist.
function(sinew_stage_files out)
  sinew_stage_names(stages)
  set(files "")
  foreach(stage IN LISTS stages)
    foreach(pattern IN LISTS ARGN)
      string(REPLACE "@stage@" ${stage} f ${pattern})
      if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${f})
        list(APPEND files ${f})
      endif()
    endforeach()
  endforeach()
  set(${out} ${files} PARENT_SCOPE)
endfunction()

# Writes <build>/generated/HEADER: one #include per stage of PATTERN (a path
# from the source root with @stage@), for the stages that have the file, in
# stage order; TARGET gets the generated tree on its include path. Rewritten
# only when its text changes, so a build that adds no layer rebuilds nothing.
function(sinew_stage_header target header pattern)
  sinew_stage_names(stages)
  string(REPLACE "@stage@" "<stage>" shown ${pattern})
  set(text "// Generated from sim_core/pipeline/stage_list.hpp by cmake/sinew_stages.cmake:\n")
  string(APPEND text "// one include per stage that has ${shown}.\n#pragma once\n\n")
  foreach(stage IN LISTS stages)
    string(REPLACE "@stage@" ${stage} f ${pattern})
    if(EXISTS ${PROJECT_SOURCE_DIR}/${f})
      string(APPEND text "#include \"${f}\"\n")
    endif()
  endforeach()
  file(CONFIGURE OUTPUT ${SINEW_GENERATED_DIR}/${header} CONTENT "${text}" @ONLY)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${SINEW_GENERATED_DIR}>)
endfunction()
