# Usage: cmake -DROOT=<source dir> [-DNINJA_FILE=<build.ninja>] [-DEXPECT_EVERY_RULE=ON]
#          -P layering_lint.cmake
# Fails when the module graph is broken:
#   sim_core/    includes anything outside sim_core/ (relative includes of
#                its own folder are fine);
#   hal/         includes firmware/ or host_tools/, or sim_core's physics
#                (only sim_core/fixed, the fixed-point maths, is allowed);
#   firmware/    includes host_tools/;
#   host_tools/  includes firmware/ other than the daemon's public headers
#                firmware/runtime/{runtime,tick_trigger,async_sink,recording,realtime,worker_pool}.hpp,
#                and firmware/rig/loaded_rig.hpp;
#   sinewd       links a library built from host_tools/ (NINJA_FILE's link line);
#   tests tree   a sim_core/, hal/, firmware/ or host_tools/ file includes a
#                file of tests/, or a CMakeLists.txt there compiles one: the
#                product never builds from its tests (a baseline a tool and a
#                test share lives in the product's tree);
#   layer names  a firmware/ source or CMake file names a physical layer (in
#                code or comments): the stage table in sim_core/pipeline is
#                the only list of layers the daemon reads, so adding a layer
#                adds no line to firmware;
#   shared names a file every layer shares names a layer outside an #include
#                line: sim_core/pipeline/ (but stage_list.hpp and each
#                stage's own stage_<name>* files, <name> as stage_list.hpp
#                lists it), host_tools/layers/ at its top (but the built-in
#                rigs' recipe, builtin_layers.*), common/ and sections/,
#                rigc's toml_layers.*, toml_reader.* and tables/rigc_table.hpp,
#                the viewer's frame_message.* and overlays/overlay.hpp, and
#                the CMakeLists.txt of sim_core/, sim_core/pipeline/,
#                host_tools/layers/, rigc and the viewer, which find a
#                layer's files from the stage list (cmake/sinew_stages.cmake):
#                a layer lives in its own files;
#   tests layout the tests tree stops mirroring the modules: a folder
#                tests/{sim_core,hal,host_tools}/<m> with no module <m> beside
#                it, or a folder directly under tests/ that is neither a
#                module tree (sim_core, hal, host_tools, firmware) nor one of
#                the cross-module suites (kSuites below).
# With EXPECT_EVERY_RULE it fails unless every rule fired: the planted tree
# (tests/lint/planted_layering) proves each rule can fail.
set(rules sim_core hal firmware host_tools link layer_names shared_names tests_tree tests_layout)
foreach(r IN LISTS rules)
  set(fired_${r} 0)
endforeach()

function(scan dir rule)
  file(GLOB_RECURSE sources "${ROOT}/${dir}/*.hpp" "${ROOT}/${dir}/*.cpp" "${ROOT}/${dir}/*.h" "${ROOT}/${dir}/*.cc")
  foreach(src IN LISTS sources)
    file(STRINGS "${src}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]*)\".*$" "\\1" path "${line}")
      set(bad "")
      if(rule STREQUAL "sim_core")
        if(path MATCHES "/" AND NOT path MATCHES "^sim_core/")
          set(bad "sim_core includes outside sim_core")
        elseif(path MATCHES "\\.\\.")
          set(bad "sim_core includes through ..")
        endif()
      elseif(rule STREQUAL "hal")
        if(path MATCHES "^(firmware|host_tools)/")
          set(bad "hal includes ${CMAKE_MATCH_1}")
        elseif(path MATCHES "^sim_core/" AND NOT path MATCHES "^sim_core/fixed/")
          set(bad "hal includes sim_core beyond its fixed-point maths")
        endif()
      elseif(rule STREQUAL "firmware")
        if(path MATCHES "^host_tools/")
          set(bad "firmware includes host_tools")
        endif()
      elseif(rule STREQUAL "host_tools")
        if(path MATCHES "^firmware/" AND NOT path MATCHES "^firmware/(runtime/(runtime|tick_trigger|async_sink|recording|realtime|worker_pool)|rig/loaded_rig)\\.hpp$")
          set(bad "host_tools includes firmware beyond its public headers")
        endif()
      endif()
      if(path MATCHES "^tests/")
        message("${src}: includes a file of tests/: ${path}")
        math(EXPR n "${fired_tests_tree} + 1")
        set(fired_tests_tree ${n})
        set(fired_tests_tree ${n} PARENT_SCOPE)
      endif()
      if(NOT bad STREQUAL "")
        message("${src}: ${bad}: ${path}")
        math(EXPR n "${fired_${rule}} + 1")
        set(fired_${rule} ${n})
        set(fired_${rule} ${n} PARENT_SCOPE)
      endif()
    endforeach()
  endforeach()
endfunction()

# A word that names a physical layer: letters around it end the match, so
# "sphere" is not "sph" but "sph_joint" is.
set(layer_word "(^|[^a-z])(sph|metaballs?|barnet|bar-net|anatomy|muscles?|tresca|elastic[ _-]skin|leman)([^a-z]|$)")
function(scan_layer_names dir)
  file(GLOB_RECURSE sources "${ROOT}/${dir}/*.hpp" "${ROOT}/${dir}/*.cpp" "${ROOT}/${dir}/*.h" "${ROOT}/${dir}/*.cc"
       "${ROOT}/${dir}/CMakeLists.txt")
  foreach(src IN LISTS sources)
    file(STRINGS "${src}" lines)
    foreach(line IN LISTS lines)
      string(TOLOWER "${line}" lower)
      if(lower MATCHES "${layer_word}")
        string(STRIP "${line}" shown)
        message("${src}: firmware names the physical layer '${CMAKE_MATCH_2}' (use the stage table): ${shown}")
        math(EXPR n "${fired_layer_names} + 1")
        set(fired_layer_names ${n})
        set(fired_layer_names ${n} PARENT_SCOPE)
      endif()
    endforeach()
  endforeach()
endfunction()

# The files every layer shares (the shared_names rule above).
function(scan_shared_names)
  set(stage_names "")
  if(EXISTS "${ROOT}/sim_core/pipeline/stage_list.hpp")
    # Read whole: its lines end in "\\", which would escape a list's ";".
    file(READ "${ROOT}/sim_core/pipeline/stage_list.hpp" list_text)
    string(REGEX MATCHALL "X\\([a-z_]+," entries "${list_text}")
    foreach(e IN LISTS entries)
      string(REGEX REPLACE "X\\(([a-z_]+)," "\\1" stage "${e}")
      list(APPEND stage_names "${stage}")
    endforeach()
  endif()
  file(GLOB pipeline_files "${ROOT}/sim_core/pipeline/*.hpp" "${ROOT}/sim_core/pipeline/*.cpp")
  set(shared "")
  foreach(f IN LISTS pipeline_files)
    get_filename_component(name "${f}" NAME)
    set(own FALSE)
    foreach(stage IN LISTS stage_names)
      if(name MATCHES "^stage_${stage}[_.]")
        set(own TRUE)
      endif()
    endforeach()
    if(NOT own AND NOT name STREQUAL "stage_list.hpp")
      list(APPEND shared "${f}")
    endif()
  endforeach()
  file(GLOB host_files "${ROOT}/host_tools/layers/*.hpp" "${ROOT}/host_tools/layers/*.cpp"
       "${ROOT}/host_tools/layers/common/*.hpp" "${ROOT}/host_tools/layers/common/*.cpp"
       "${ROOT}/host_tools/layers/sections/*.hpp" "${ROOT}/host_tools/layers/sections/*.cpp"
       "${ROOT}/host_tools/rigc/toml_layers.*" "${ROOT}/host_tools/rigc/toml_reader.*"
       "${ROOT}/host_tools/rigc/tables/rigc_table.hpp" "${ROOT}/host_tools/view/frame_message.*"
       "${ROOT}/host_tools/view/overlays/overlay.hpp" "${ROOT}/sim_core/CMakeLists.txt"
       "${ROOT}/sim_core/pipeline/CMakeLists.txt" "${ROOT}/host_tools/layers/CMakeLists.txt"
       "${ROOT}/host_tools/rigc/CMakeLists.txt" "${ROOT}/host_tools/view/CMakeLists.txt"
       "${ROOT}/cmake/sinew_stages.cmake")
  list(FILTER host_files EXCLUDE REGEX "/builtin_layers\\.[a-z]+$")
  list(APPEND shared ${host_files})
  foreach(src IN LISTS shared)
    file(STRINGS "${src}" lines)
    foreach(line IN LISTS lines)
      string(TOLOWER "${line}" lower)
      if(NOT lower MATCHES "^[ \t]*#[ \t]*include" AND lower MATCHES "${layer_word}")
        string(STRIP "${line}" shown)
        message("${src}: a file every layer shares names the layer '${CMAKE_MATCH_2}': ${shown}")
        math(EXPR n "${fired_shared_names} + 1")
        set(fired_shared_names ${n})
        set(fired_shared_names ${n} PARENT_SCOPE)
      endif()
    endforeach()
  endforeach()
endfunction()

scan(sim_core sim_core)
scan(hal hal)
scan(firmware firmware)
scan(host_tools host_tools)
scan_layer_names(firmware)
scan_shared_names()

# A product CMakeLists.txt that compiles a source of tests/.
foreach(dir sim_core hal firmware host_tools)
  file(GLOB_RECURSE lists "${ROOT}/${dir}/CMakeLists.txt")
  foreach(list_file IN LISTS lists)
    file(STRINGS "${list_file}" lines REGEX "tests/[^ )\"]*\\.(cpp|cc|c)")
    foreach(line IN LISTS lines)
      message("${list_file}: compiles a file of tests/: ${line}")
      math(EXPR fired_tests_tree "${fired_tests_tree} + 1")
    endforeach()
  endforeach()
endforeach()

# The tests tree mirrors the modules (tests/CMakeLists.txt says why).
cmake_policy(SET CMP0057 NEW)  # IN_LIST in script mode
set(kSuites sim_core hal host_tools firmware determinism property integration fuzz lint kernel oracle bench support data)
file(GLOB test_dirs LIST_DIRECTORIES true "${ROOT}/tests/*")
foreach(d IN LISTS test_dirs)
  get_filename_component(name "${d}" NAME)
  if(IS_DIRECTORY "${d}" AND NOT name IN_LIST kSuites)
    message("tests/${name}: neither a module tree nor a cross-module suite")
    math(EXPR fired_tests_layout "${fired_tests_layout} + 1")
  endif()
endforeach()
foreach(tree sim_core hal host_tools)
  file(GLOB mirrors LIST_DIRECTORIES true "${ROOT}/tests/${tree}/*")
  foreach(d IN LISTS mirrors)
    get_filename_component(name "${d}" NAME)
    if(IS_DIRECTORY "${d}" AND NOT IS_DIRECTORY "${ROOT}/${tree}/${name}")
      message("tests/${tree}/${name}: no module ${tree}/${name} to mirror")
      math(EXPR fired_tests_layout "${fired_tests_layout} + 1")
    endif()
  endforeach()
endforeach()

if(DEFINED NINJA_FILE)
  if(NOT EXISTS "${NINJA_FILE}")
    message(FATAL_ERROR "layering lint: ${NINJA_FILE} not found")
  endif()
  file(READ "${NINJA_FILE}" ninja)
  string(REGEX MATCH "\nbuild firmware/sinewd:[^\n]*\n([ ][^\n]*\n)*" block "${ninja}")
  if(block STREQUAL "")
    message(FATAL_ERROR "layering lint: no link statement for firmware/sinewd in ${NINJA_FILE}")
  endif()
  string(REGEX MATCH "LINK_LIBRARIES = [^\n]*" libs "${block}")
  string(REGEX MATCHALL "[^ ]*host_tools/[^ ]*" host_libs "${libs}")
  foreach(lib IN LISTS host_libs)
    message("sinewd links a host_tools library: ${lib}")
    math(EXPR fired_link "${fired_link} + 1")
  endforeach()
endif()

set(total 0)
foreach(r IN LISTS rules)
  math(EXPR total "${total} + ${fired_${r}}")
endforeach()
if(EXPECT_EVERY_RULE)
  foreach(r IN LISTS rules)
    if(fired_${r} EQUAL 0)
      message(FATAL_ERROR "layering lint: the ${r} rule did not fire on the planted tree")
    endif()
  endforeach()
  message("layering lint: every rule fired on the planted tree (${total} violations)")
elseif(total GREATER 0)
  message(FATAL_ERROR "layering lint: ${total} violation(s)")
else()
  message("layering lint: the module graph is clean")
endif()
