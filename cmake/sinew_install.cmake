# Install rules. Component `core`: sim_core's static libraries, its public
# headers (not the vector kernels' internals) under include/sinew, the C API
# header <sinew/sinew.h>, the CMake package (find_package(sinew): sinew::core) and
# sinew.pc. Component `runtime`: sinewd and its default configuration;
# `tools`: the host tools that were built.
include(CMakePackageConfigHelpers)

get_property(core_modules GLOBAL PROPERTY SINEW_CORE_MODULES)
install(TARGETS ${core_modules} sinew_core EXPORT sinewTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT core
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sinew)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sim_core DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sinew COMPONENT core
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h"
        # The kernels' internals: a step's stages and the vector kernels.
        PATTERN "kernels.hpp" EXCLUDE PATTERN "isa_region.hpp" EXCLUDE PATTERN "avx2_lanes.hpp" EXCLUDE
        PATTERN "lbs_blocks.hpp" EXCLUDE PATTERN "skinning_detail.hpp" EXCLUDE)
# The headers the build generates from the stage list (cmake/sinew_stages.cmake).
install(FILES ${SINEW_GENERATED_DIR}/sim_core/pipeline/stage_headers.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sinew/sim_core/pipeline COMPONENT core)
# The C API as <sinew/sinew.h>, as Box2D's <box2d/box2d.h>.
install(FILES ${PROJECT_SOURCE_DIR}/sim_core/capi/sinew.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sinew COMPONENT core)
install(EXPORT sinewTargets NAMESPACE sinew:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sinew COMPONENT core)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/sinewConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/sinewConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sinew)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sinewConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/sinewConfig.cmake ${PROJECT_BINARY_DIR}/sinewConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sinew COMPONENT core)

# pkg-config: the static libraries in one group (they refer to each other).
set(pc_libs "")
foreach(m IN LISTS core_modules)
  string(APPEND pc_libs " -l${m}")
endforeach()
configure_file(${PROJECT_SOURCE_DIR}/cmake/sinew.pc.in ${PROJECT_BINARY_DIR}/sinew.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sinew.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT core)

if(TARGET sinewd)
  install(TARGETS sinewd RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/config/default.toml
          DESTINATION ${CMAKE_INSTALL_DATADIR}/sinew COMPONENT runtime)
  # The service (docs/service.md): its unit, its user, its documentation.
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/systemd/sinewd.service DESTINATION lib/systemd/system COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/systemd/sinew.sysusers DESTINATION lib/sysusers.d RENAME sinew.conf
          COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/docs/service.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
endif()
foreach(tool rigc sinew-run sinew-export sinew-log rigsim sinew-pose sinew-receive)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
  endif()
endforeach()
