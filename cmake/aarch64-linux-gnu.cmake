# SPDX-License-Identifier: BSD-2-Clause
# Cross-compiling for 64-bit Arm Linux with Debian's GNU toolchain (g++-aarch64-linux-gnu).
# scripts/check-neon.sh uses it with SVC_KERNELS_ONLY, which needs no library of the
# target beyond the C++ runtime the toolchain brings; tests and programs built with it run
# under qemu-aarch64, with the toolchain's sysroot for the dynamic loader and libraries.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
