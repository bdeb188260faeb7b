# Cross build for 32-bit ARM hard-float (armhf) with Debian's gcc cross toolchain.
# Here `long` is 32 bits and `char` is unsigned: sim_core uses fixed-width types only.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-linux-gnueabihf-gcc)
set(CMAKE_CXX_COMPILER arm-linux-gnueabihf-g++)
set(CMAKE_FIND_ROOT_PATH /usr/arm-linux-gnueabihf)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-arm-static;-L;/usr/arm-linux-gnueabihf)
# gcc notes every function taking a std::span or an iterator by value that
# its parameter passing changed in GCC 7.1: a note for mixing objects built
# by gcc < 7.1 with newer ones, which this build never does.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
