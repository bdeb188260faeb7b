# Install rules. Component `core`: sim_core's static libraries, its public
# headers (not the vector kernels' internals) under include/sinew, the C API
# header <sinew/sinew.h>, the CMake package (find_package(sinew): sinew::core) and
# sinew.pc. Component `hal`: hal's static libraries (drivers, their simulated
# twins, the outputs) and headers, as sinew::hal in the same package.
# Component `runtime`: sinewd, its default configuration and its systemd
# unit; `tools`: the host tools that were built. The Debian packages
# (cmake/sinew_package.cmake) are these components.
include(CMakePackageConfigHelpers)

# The Debian layout (scripts/package.sh turns it on with the prefix /usr): the
# unit in /lib/systemd/system (bookworm's systemd and lintian look there), the
# configuration as the conffile /etc/sinew/sinewd.toml, and each package's
# copyright and changelog. Off, everything stays under the prefix.
option(SINEW_DEBIAN_LAYOUT "Install in the Debian packages' layout (/etc/sinew, /lib/systemd/system, per-package copyright)" OFF)
if(SINEW_DEBIAN_LAYOUT)
  set(sinew_unit_dir /lib/systemd/system)
  # Debian's multiarch library directory, for the cross-built packages too
  # (GNUInstallDirs chooses it for native builds only).
  if(CMAKE_LIBRARY_ARCHITECTURE)
    set(CMAKE_INSTALL_LIBDIR lib/${CMAKE_LIBRARY_ARCHITECTURE})
  endif()
else()
  set(sinew_unit_dir lib/systemd/system)
endif()

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

# hal as sinew::hal: every hal library this build has, in its own export set
# (sinewHalTargets.cmake), so that a core-only consumer needs none of hal's
# third-party packages. sinewConfig.cmake finds those (libgpiod, libmodbus,
# libzstd, Cyclone DDS) when the hal targets are installed.
set(sinew_hal_libraries "")
set(sinew_hal_private_libraries "")  # linked by hal's libraries only: the outputs' xxHash, dds' message types
foreach(lib sinew_hal_common sinew_units sinew_hal_sweep sinew_hal_sim sinew_hal_output sinew_hal_can sinew_hal_can_sim
            sinew_hal_gpio sinew_hal_gpio_sim sinew_hal_modbus sinew_hal_modbus_sim sinew_hal_dds)
  if(TARGET ${lib})
    list(APPEND sinew_hal_libraries ${lib})
  endif()
endforeach()
foreach(lib sinew_xxhash sinew_ros2_msgs)
  if(TARGET ${lib})
    list(APPEND sinew_hal_private_libraries ${lib})
  endif()
endforeach()
set(SINEW_HAL_HAS_DDS OFF)
if(TARGET sinew_hal_dds)
  set(SINEW_HAL_HAS_DDS ON)
endif()
if(TARGET sinew_hal_common)
  add_library(sinew_hal INTERFACE)
  target_link_libraries(sinew_hal INTERFACE ${sinew_hal_libraries})
  set_target_properties(sinew_hal PROPERTIES EXPORT_NAME hal)
  install(TARGETS ${sinew_hal_libraries} sinew_hal ${sinew_hal_private_libraries}
          EXPORT sinewHalTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT hal)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/hal DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sinew COMPONENT hal
          FILES_MATCHING PATTERN "*.hpp" PATTERN "idl" EXCLUDE
          # hal/dds's private headers (they name Cyclone DDS's types).
          PATTERN "dds_writer.hpp" EXCLUDE PATTERN "dds_entity.hpp" EXCLUDE PATTERN "qos.hpp" EXCLUDE)
  install(EXPORT sinewHalTargets NAMESPACE sinew:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sinew COMPONENT hal)
endif()
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
# Relocatable: the prefix as a path from the .pc file's directory (libdir is
# lib, or lib/<multiarch> under /usr).
file(RELATIVE_PATH sinew_pc_to_prefix /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
string(REGEX REPLACE "/$" "" sinew_pc_to_prefix "${sinew_pc_to_prefix}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/sinew.pc.in ${PROJECT_BINARY_DIR}/sinew.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sinew.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT core)

if(TARGET sinewd)
  install(TARGETS sinewd RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/config/default.toml
          DESTINATION ${CMAKE_INSTALL_DATADIR}/sinew COMPONENT runtime)
  if(SINEW_DEBIAN_LAYOUT)
    install(FILES ${PROJECT_SOURCE_DIR}/firmware/config/default.toml DESTINATION /etc/sinew RENAME sinewd.toml
            COMPONENT runtime)
  endif()
  # The service (docs/service.md): its unit, its user, its documentation.
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/systemd/sinewd.service DESTINATION ${sinew_unit_dir} COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/systemd/sinew.sysusers DESTINATION lib/sysusers.d RENAME sinew.conf
          COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/firmware/systemd/60-sinew.rules DESTINATION lib/udev/rules.d COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/docs/service.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
endif()
foreach(tool rigc sinew-run sinew-export sinew-log rigsim sinew-pose sinew-receive)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
  endif()
endforeach()
