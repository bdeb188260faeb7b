# Usage: cmake -DBUILD_DIR= -DWORK= -DSOURCE= -DRIG= -DGENERATOR= -DCXX= -P consumer_test.cmake
# Installs the core and hal components of BUILD_DIR into WORK/prefix, builds
# the consumer project (SOURCE) against it with find_package(sinew), builds
# consumer.c again with pkg-config and cc alone, runs the four on RIG
# (consumer_hal also through hal's frame log), and fails unless each
# succeeds and all print the same line. A second prefix with the core alone
# must serve a core-only consumer and refuse one that asks for hal.
file(REMOVE_RECURSE ${WORK})
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
run("cmake --install (core)" ${CMAKE_COMMAND} --install ${BUILD_DIR} --component core --prefix ${WORK}/prefix)
run("cmake --install (hal)" ${CMAKE_COMMAND} --install ${BUILD_DIR} --component hal --prefix ${WORK}/prefix)
foreach(f include/sinew/sinew.h include/sinew/sim_core/pipeline/pipeline.hpp include/sinew/sim_core/pipeline/stage_headers.hpp
          include/sinew/hal/output/frame_log_writer.hpp lib/cmake/sinew/sinewConfig.cmake
          lib/cmake/sinew/sinewHalTargets.cmake lib/pkgconfig/sinew.pc)
  if(NOT EXISTS ${WORK}/prefix/${f})
    file(GLOB_RECURSE found RELATIVE ${WORK}/prefix ${WORK}/prefix/*sinew*)
    message(FATAL_ERROR "not installed: ${f} (installed: ${found})")
  endif()
endforeach()
if(EXISTS ${WORK}/prefix/include/sinew/sim_core/metaballs/kernels.hpp)
  message(FATAL_ERROR "a kernel's internal header was installed: sim_core/metaballs/kernels.hpp")
endif()
run("configure the consumer" ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${WORK}/prefix -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release)
run("build the consumer" ${CMAKE_COMMAND} --build ${WORK}/build)
run("the C consumer" ${WORK}/build/consumer_c ${RIG})
set(c_line "${last_output}")
run("the C++ consumer" ${WORK}/build/consumer_cpp ${RIG})
set(cpp_line "${last_output}")
run("the hal consumer" ${WORK}/build/consumer_hal ${RIG} ${WORK}/consumer_hal.log)
set(hal_line "${last_output}")
# pkg-config, as a Makefile or another build system would.
set(ENV{PKG_CONFIG_PATH} ${WORK}/prefix/lib/pkgconfig)
run("pkg-config" pkg-config --cflags --libs sinew)
string(STRIP "${last_output}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
run("cc with pkg-config" cc -O2 ${SOURCE}/consumer.c ${flags} -o ${WORK}/consumer_pkgconfig)
run("the pkg-config consumer" ${WORK}/consumer_pkgconfig ${RIG})
set(pc_line "${last_output}")
message("C:          ${c_line}C++:        ${cpp_line}C++ + hal:  ${hal_line}pkg-config: ${pc_line}")
if(NOT c_line STREQUAL cpp_line OR NOT c_line STREQUAL pc_line OR NOT c_line STREQUAL hal_line)
  message(FATAL_ERROR "the consumers disagree")
endif()
if(NOT c_line MATCHES "moved 1")
  message(FATAL_ERROR "the skin did not move")
endif()

# The core alone: a core-only consumer builds, one that asks for hal is
# refused at configure time with the reason.
run("cmake --install (core only)" ${CMAKE_COMMAND} --install ${BUILD_DIR} --component core --prefix ${WORK}/core-only)
run("configure a core-only consumer" ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build-core-only -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${WORK}/core-only -DCMAKE_CXX_COMPILER=${CXX} -DSINEW_CONSUMER_HAL=OFF)
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build-core-only-hal -G ${GENERATOR}
                -DCMAKE_PREFIX_PATH=${WORK}/core-only -DCMAKE_CXX_COMPILER=${CXX}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES "sinew::hal is not installed")
  message(FATAL_ERROR "asking for hal from a core-only install was not refused with the reason (${rc}):\n${out}\n${err}")
endif()
