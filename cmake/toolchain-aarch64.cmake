# Cross build for 64-bit ARM (aarch64) with Debian's gcc cross toolchain.
# Tests run under qemu-user; only the -static emulator exists here and
# binfmt_misc is not mounted, so the emulator and its sysroot prefix are explicit.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Two roots: the cross toolchain's own (libc, libstdc++), and / for Debian's
# arm64 multiarch packages (scripts/install-deps.sh test): their libraries and
# CMake configs live under /usr/lib/aarch64-linux-gnu, their headers and the
# architecture-independent configs (CLI11) under /usr/include and /usr/share.
# Host libraries stay out of reach: they live under /usr/lib/x86_64-linux-gnu.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu /)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# pkgconf's cross personality: reads the arm64 .pc files only.
set(PKG_CONFIG_EXECUTABLE aarch64-linux-gnu-pkg-config CACHE FILEPATH "pkg-config for the aarch64 target")
# The tests run on Debian's arm64 multiarch runtime (libc6:arm64 and
# libstdc++6:arm64, from scripts/install-deps.sh test), as on an arm64 board:
# hence the prefix /, not the cross toolchain's /usr/aarch64-linux-gnu. With
# that prefix the toolchain's ld.so would load the multiarch libc.so.6 (first
# on its search path) from a different glibc build, and pthread_create hangs.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static;-L;/)
