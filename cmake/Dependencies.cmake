# SPDX-License-Identifier: Apache-2.0
# Third-party dependencies: Debian packages only, found with find_package / pkg-config.
find_package(PkgConfig REQUIRED)
pkg_check_modules(SOCKETCAN REQUIRED IMPORTED_TARGET libsocketcan)
find_package(fmt REQUIRED)
find_package(tl-expected REQUIRED)
find_package(Threads REQUIRED)
find_package(Eigen3 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
# The fuzz build compiles the simulator (fuzz_slave_replies), whose daemons use CLI11.
if(CODRIVE_BUILD_TOOLS OR CODRIVE_FUZZ)
    find_package(CLI11 REQUIRED)
    # codrive-dump reads Vector BLF files, whose containers are zlib streams (zlib1g-dev).
    find_package(ZLIB REQUIRED)
endif()
# The EtherCAT master reads ESI XML files (ETG.2000: bus-file `esi:`, `codrive esi show`) and
# `codrive esi export` writes them, with Debian's libpugixml-dev.
find_package(pugixml REQUIRED)
if(CODRIVE_BUILD_TESTS)
    find_package(GTest REQUIRED)
endif()
if(CODRIVE_BUILD_BENCH)
    find_package(benchmark REQUIRED)
endif()
# The Python module (python/, docs/python.md): Debian's /usr/bin/python3 (a python3 earlier in
# PATH may be another interpreter the module would not load in) and pybind11-dev. Built by
# default when both are found; -DCODRIVE_BUILD_PYTHON=ON makes their absence an error.
if(NOT DEFINED CODRIVE_BUILD_PYTHON OR CODRIVE_BUILD_PYTHON)
    if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
        set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python the module is built for")
    endif()
    find_package(Python 3 COMPONENTS Interpreter Development.Module QUIET)
    if(Python_FOUND)
        find_package(pybind11 CONFIG QUIET)
    endif()
endif()
