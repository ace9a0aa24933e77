# CMake toolchain file: cross-compile libpbf for 64-bit Windows with MinGW-w64 on Debian/Ubuntu
# (packages g++-mingw-w64-x86-64-posix and gcc-mingw-w64-x86-64-posix).
#
#   cmake -S . -B build-mingw -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64-x86_64.cmake \
#         -DPBF_WITH_CUDA=OFF -DEigen3_DIR=/usr/share/eigen3/cmake
#
# scripts/build_windows_dll.sh does exactly this. The posix-thread variant of the compilers is
# the one with std::thread (on winpthreads); the win32-thread variant has none. libpbf's CPU loops
# use no OpenMP on Windows (native/exec/cpu_pool.h).
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)

set(PBF_MINGW_TRIPLE x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${PBF_MINGW_TRIPLE}-gcc-posix)
set(CMAKE_CXX_COMPILER ${PBF_MINGW_TRIPLE}-g++-posix)
set(CMAKE_RC_COMPILER ${PBF_MINGW_TRIPLE}-windres)

# Libraries and headers come from the MinGW sysroot only, never from the host's /usr.
# (Header-only packages of the host, Eigen, are passed in explicitly with Eigen3_DIR.)
set(CMAKE_FIND_ROOT_PATH /usr/${PBF_MINGW_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Link libgcc, libstdc++ and winpthreads statically into pbf.dll and the test programs, so that
# they need no MinGW runtime DLLs (libgcc_s_seh-1, libstdc++-6, libwinpthread-1): only Windows'
# own DLLs.
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-static")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")

# Cross-built programs run under Wine where it is installed (ctest, add_test).
find_program(PBF_WINE NAMES wine wine64)
if(PBF_WINE)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${PBF_WINE})
endif()
