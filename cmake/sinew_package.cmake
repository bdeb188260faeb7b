# The Debian packages (CPack, DEB generator), one per install component
# (cmake/sinew_install.cmake):
#   sinew         runtime  sinewd, its systemd unit and user, the default
#                          configuration as the conffile /etc/sinew/sinewd.toml
#   sinew-tools   tools    rigc, sinew-run, sinew-export and the other host tools
#   libsinew-dev  core+hal the static libraries, headers, CMake package and
#                          pkg-config file
# for the build's architecture (amd64; arm64 from the aarch64 preset, armhf
# from the armhf preset, whose libsinew-dev holds the core alone). Build them
# with scripts/package.sh, which turns on SINEW_DEBIAN_LAYOUT with the prefix
# /usr and runs lintian on the result.

# Each package's copyright and changelog (Debian policy 12.5 and 12.7), and
# the service's maintainer scripts and conffile, under the names dpkg gives them.
set(sinew_deb_dir ${PROJECT_BINARY_DIR}/debian)
set(sinew_deb_source ${PROJECT_SOURCE_DIR}/packaging/debian)
file(STRINGS ${sinew_deb_source}/changelog sinew_changelog_head LIMIT_COUNT 1)
if(NOT sinew_changelog_head MATCHES "^sinew \\(${PROJECT_VERSION}\\) ")
  message(FATAL_ERROR "packaging/debian/changelog's first entry (${sinew_changelog_head}) is not version ${PROJECT_VERSION}")
endif()
file(MAKE_DIRECTORY ${sinew_deb_dir}/runtime)
foreach(script postinst prerm postrm)
  file(COPY_FILE ${sinew_deb_source}/sinew.${script} ${sinew_deb_dir}/runtime/${script} ONLY_IF_DIFFERENT)
endforeach()
file(COPY_FILE ${sinew_deb_source}/sinew.conffiles ${sinew_deb_dir}/runtime/conffiles ONLY_IF_DIFFERENT)
# changelog.gz as dpkg-deb would want it: gzip -9n (no name or time stamp:
# the same bytes from every build).
find_program(SINEW_GZIP gzip)
if(SINEW_DEBIAN_LAYOUT AND SINEW_GZIP)
  execute_process(COMMAND ${SINEW_GZIP} -9nc ${sinew_deb_source}/changelog OUTPUT_FILE ${sinew_deb_dir}/changelog.gz
                  COMMAND_ERROR_IS_FATAL ANY)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${sinew_deb_source}/changelog)
endif()

# Manual pages: scripts/package.sh writes man/<program>.1.gz in the build
# tree with help2man from each program's --help (Debian policy 12.1); the
# programs and their components are listed here for it, with their paths.
set(sinew_man_programs "")
function(sinew_package_man_page component target)
  if(SINEW_DEBIAN_LAYOUT AND TARGET ${target})
    install(FILES ${PROJECT_BINARY_DIR}/man/${target}.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1
            COMPONENT ${component} OPTIONAL)
    set(sinew_man_programs "${sinew_man_programs}${target}=$<TARGET_FILE:${target}>\n" PARENT_SCOPE)
  endif()
endfunction()

function(sinew_package_docs component package)
  if(SINEW_DEBIAN_LAYOUT)
    install(FILES ${sinew_deb_source}/copyright ${sinew_deb_dir}/changelog.gz
            DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${package} COMPONENT ${component})
  endif()
endfunction()

# The packages' architecture is the target's, not the build machine's.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE amd64)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64)$")
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^arm")
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE armhf)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME sinew)
set(CPACK_PACKAGE_VENDOR "the sinew authors")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "sinew developers <sinew@example.org>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/packages)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)

set(CPACK_COMPONENTS_ALL core)
set(CPACK_COMPONENT_CORE_GROUP dev)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME libsinew-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_DESCRIPTION
    "sinew's deterministic core and hardware abstraction (static libraries)
The fixed-point core of sinew: rig loading, kinematics, LBS and DQS skinning
and the physical layers (SPH elastic joints, metaballs, muscles, elastic
skin, bar-nets), with bit-identical output on every architecture, no
allocation after initialisation and a C API (sinew/sinew.h). With it, sinew's
hardware abstraction: SocketCAN, libgpiod and libmodbus inputs with their
simulated twins, the frame log, UDP and CAN outputs. A CMake package
(find_package(sinew): sinew::core, sinew::hal) and a pkg-config file.")
sinew_package_docs(core libsinew-dev)
if(TARGET sinew_hal)
  list(APPEND CPACK_COMPONENTS_ALL hal)
  set(CPACK_COMPONENT_HAL_GROUP dev)
  # hal's libraries are static: a consumer links their libraries too.
  set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libgpiod-dev, libmodbus-dev, libzstd-dev")
  if(TARGET sinew_hal_dds)
    string(APPEND CPACK_DEBIAN_DEV_PACKAGE_DEPENDS ", cyclonedds-dev")
  endif()
endif()

if(TARGET sinewd)
  list(APPEND CPACK_COMPONENTS_ALL runtime)
  set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME sinew)
  set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION misc)
  set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
      "deterministic runtime turning joint angles into a deformed skin and pose
sinewd reads a rig's joint angles from SocketCAN, GPIO encoders, Modbus or
ROS 2 (DDS), steps sinew's fixed-point pipeline (skinning and physical
layers) at a fixed rate, and sends the pose and the deformed skin to a frame
log, UDP, CAN or ROS 2. It runs as a hardened systemd service (sinewd.service,
not enabled at installation) with a watchdog on its tick loop, as the user
sinew, with its configuration in /etc/sinew/sinewd.toml.")
  # The unit's user comes from sysusers.d (systemd) or adduser.
  set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "systemd")
  set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA
      ${sinew_deb_dir}/runtime/postinst ${sinew_deb_dir}/runtime/prerm ${sinew_deb_dir}/runtime/postrm)
  if(SINEW_DEBIAN_LAYOUT)
    list(APPEND CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA ${sinew_deb_dir}/runtime/conffiles)
  endif()
  sinew_package_docs(runtime sinew)
  sinew_package_man_page(runtime sinewd)
endif()

set(sinew_tools_built OFF)
foreach(tool rigc sinew-run sinew-export sinew-log rigsim sinew-pose sinew-receive)
  if(TARGET ${tool})
    set(sinew_tools_built ON)
  endif()
endforeach()
if(sinew_tools_built)
  list(APPEND CPACK_COMPONENTS_ALL tools)
  set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME sinew-tools)
  set(CPACK_DEBIAN_TOOLS_PACKAGE_SECTION devel)
  set(CPACK_COMPONENT_TOOLS_DESCRIPTION
      "sinew's offline tools: rig compiler, simulated rig, export and logs
rigc compiles a rig (glTF skin or sinew's built-in rigs, with its physical
layers) into the versioned binary blob sinewd and the core load; sinew-run
steps it offline; rigsim plays a simulated rig onto CAN, GPIO or Modbus;
sinew-export writes glTF; sinew-log, sinew-pose and sinew-receive read frame
logs and live output.")
  sinew_package_docs(tools sinew-tools)
  foreach(tool rigc sinew-run sinew-export sinew-log rigsim sinew-pose sinew-receive)
    sinew_package_man_page(tools ${tool})
  endforeach()
endif()
if(SINEW_DEBIAN_LAYOUT)
  file(GENERATE OUTPUT ${sinew_deb_dir}/man-programs.txt CONTENT "${sinew_man_programs}")
endif()

include(CPack)
